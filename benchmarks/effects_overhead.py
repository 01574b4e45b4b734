"""Zero cost when off: the elastic default scene and a dogbone, timed on the elastic code path and
with an inert declared effect (viscoelastic with β = 0: the history is integrated, the result is
the elastic one), optionally also on a baseline revision from before the effects existed.

    python benchmarks/effects_overhead.py [--repeat 3] [--baseline 821b6ca]

Every run is a fresh subprocess (imports paid equally). The variants of a scene run interleaved,
round by round (the order rotating), so on a shared machine each round's runs see about the same
load; the table gives the best solve time of each variant over ``--repeat`` rounds and the
*median of the per-round ratios* (paired, so a load swing between rounds cancels), plus the load
average before and after. The elastic path builds a HyperelasticBody exactly as before: no
state, no extra assembly, no time.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
import io
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENES = {"default block": ROOT / "vlab" / "scenes" / "default.toml",
          "dogbone ISO 37-2": ROOT / "specimens" / "dogbone-iso37-2.toml"}
INERT = {"effects": {"viscoelastic": {"tau": [1.0], "beta": [0.0]}}, "test.ramp_time": 1.0}

ONE = """
import json, sys, time, tomllib
from vlab.scene import parse_scene
from vlab.run import run_scene
data = tomllib.loads(open(sys.argv[1]).read())
if sys.argv[2] == "inert":
    data["effects"] = {"viscoelastic": {"tau": [1.0], "beta": [0.0]}}
    data["test"]["ramp_time"] = 1.0
r = run_scene(parse_scene(data))
print(json.dumps({"solve_s": r.timing["solve_s"], "total_s": r.timing["total_s"],
                  "force": r.curve.force[0][-1], "body": type(r.solver.body).__name__}))
"""


def one(source: Path, scene: Path, variant: str) -> dict:
    out = subprocess.run([sys.executable, "-c", ONE, str(scene), variant], cwd=source, check=True,
                         capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def rounds(cells: dict[str, tuple[Path, str]], scene: Path, repeat: int) -> dict[str, list[dict]]:
    """``repeat`` rounds, each running every cell (source, variant) once, the order rotating."""
    names = list(cells)
    runs: dict[str, list[dict]] = {n: [] for n in names}
    for k in range(repeat):
        for n in names[k % len(names):] + names[:k % len(names)]:
            source, variant = cells[n]
            runs[n].append(one(source, scene, variant))
    return runs


def _paired_ratio(a: list[dict], b: list[dict]) -> float:
    return statistics.median(x["solve_s"] / y["solve_s"] for x, y in zip(a, b))


def export(rev: str, folder: Path) -> Path:
    """The baseline revision's tree (git archive) in ``folder``."""
    data = subprocess.run(["git", "archive", rev], cwd=ROOT, check=True, capture_output=True).stdout
    tarfile.open(fileobj=io.BytesIO(data)).extractall(folder)
    return folder


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--baseline", default=None, help="git revision without effects, e.g. 821b6ca")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        base = export(args.baseline, Path(tmp)) if args.baseline else None
        print(f"load average before: {os.getloadavg()[0]:.2f}; {args.repeat} interleaved rounds")
        print("| scene | elastic best s | inert effect best s | median ratio inert/elastic |"
              + (" baseline elastic best s | median ratio elastic/baseline |" if base else ""))
        print("|---|---|---|---|" + ("---|---|" if base else ""))
        for name, scene in SCENES.items():
            cells = {"elastic": (ROOT, "elastic"), "inert": (ROOT, "inert")}
            if base:
                cells["baseline"] = (base, "elastic")
            runs = rounds(cells, scene, args.repeat)
            assert all(r["body"] == "HyperelasticBody" for r in runs["elastic"])
            assert all(r["body"] == "HistoryBody" for r in runs["inert"])
            fastest = {n: min(r["solve_s"] for r in v) for n, v in runs.items()}
            row = (f"| {name} | {fastest['elastic']:.3f} | {fastest['inert']:.3f} | "
                   f"{_paired_ratio(runs['inert'], runs['elastic']):.3f} |")
            if base:
                row += (f" {fastest['baseline']:.3f} | "
                        f"{_paired_ratio(runs['elastic'], runs['baseline']):.3f} |")
            print(row, flush=True)
        print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
