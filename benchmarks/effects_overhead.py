"""Zero cost when off: the elastic default scene and a dogbone, timed on the elastic code path and
with an inert declared effect (viscoelastic with β = 0: the history is integrated, the result is
the elastic one), optionally also on a baseline revision from before the effects existed.

    python benchmarks/effects_overhead.py [--repeat 3] [--baseline 821b6ca]

Every run is a fresh subprocess (imports paid equally); the best of ``--repeat`` solve times
counts. Prints a table with the ratios (inert effect / elastic; elastic / baseline elastic). The
elastic path builds a HyperelasticBody exactly as before: no state, no extra assembly, no time.
"""

from __future__ import annotations

import argparse
import json
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
                  "force": r.curve.force[0][-1], "body": type(r.extra["body"]).__name__}))
"""


def one(source: Path, scene: Path, variant: str) -> dict:
    out = subprocess.run([sys.executable, "-c", ONE, str(scene), variant], cwd=source, check=True,
                         capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def best(source: Path, scene: Path, variant: str, repeat: int) -> dict:
    runs = [one(source, scene, variant) for _ in range(repeat)]
    return min(runs, key=lambda r: r["solve_s"])


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
        print("| scene | elastic solve s | inert effect solve s | ratio inert/elastic |"
              + (" baseline elastic s | ratio elastic/baseline |" if base else ""))
        print("|---|---|---|---|" + ("---|---|" if base else ""))
        for name, scene in SCENES.items():
            elastic = best(ROOT, scene, "elastic", args.repeat)
            inert = best(ROOT, scene, "inert", args.repeat)
            assert elastic["body"] == "HyperelasticBody" and inert["body"] == "HistoryBody"
            row = (f"| {name} | {elastic['solve_s']:.3f} | {inert['solve_s']:.3f} | "
                   f"{inert['solve_s'] / elastic['solve_s']:.3f} |")
            if base:
                old = best(base, scene, "elastic", args.repeat)
                row += f" {old['solve_s']:.3f} | {elastic['solve_s'] / old['solve_s']:.3f} |"
            print(row, flush=True)


if __name__ == "__main__":
    main()
