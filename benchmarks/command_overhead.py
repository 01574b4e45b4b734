"""What `vlab run SCENE --no-render --no-estimate` costs end to end, phase by phase.

    python benchmarks/command_overhead.py [SCENE] [--repeat 3]

Each repeat runs the command in a fresh process (``python -m vlab run ... -q``) and, separately,
the same phases in a fresh process with a clock around each: interpreter + ``import vlab.cli``,
``run_scene`` (the results.json ``timing.total_s`` is inside it), ``write_run`` without renders
(results.json, CSV, PNGs, VTU/PVD, HTML). Wall and CPU (user + system of all threads) seconds; on
a loaded machine the CPU figures are the steadier ones. Best of the repeats.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PHASES = r"""
import json, os, sys, time
from pathlib import Path
def cpu():
    t = os.times()
    return t.user + t.system
w0, c0 = time.perf_counter(), cpu()
import vlab.cli  # noqa: F401  what the command imports before it runs
from vlab.report.writer import ReportOptions, write_run
from vlab.run import run_scene
from vlab.scene import load_scene
w1, c1 = time.perf_counter(), cpu()
scene = load_scene(Path(sys.argv[1]))
result = run_scene(scene)
w2, c2 = time.perf_counter(), cpu()
write_run(result, Path(sys.argv[2]), None, ReportOptions(render=False))
w3, c3 = time.perf_counter(), cpu()
print("RESULT " + json.dumps({"import": [w1 - w0, c1 - c0], "run_scene": [w2 - w1, c2 - c1],
                              "write_run": [w3 - w2, c3 - c2], "solve_total_s": result.timing["total_s"]}))
"""


def command(scene: Path, out: Path) -> tuple[float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "vlab", "run", str(scene), "--no-render", "--no-estimate",
                    "--out", str(out), "-q"], check=True, cwd=ROOT, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.perf_counter() - t0, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def phases(scene: Path, out: Path) -> dict:
    proc = subprocess.run([sys.executable, "-c", PHASES, str(scene), str(out)], capture_output=True,
                          text=True, cwd=ROOT, check=True)
    return json.loads([x for x in proc.stdout.splitlines() if x.startswith("RESULT ")][0][7:])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", nargs="?", default=str(ROOT / "benchmarks" / "block16.toml"))
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    runs, parts = [], []
    with tempfile.TemporaryDirectory() as scratch:
        for i in range(args.repeat):
            runs.append(command(Path(args.scene), Path(scratch) / f"cmd{i}"))
            parts.append(phases(Path(args.scene), Path(scratch) / f"ph{i}"))
    wall, cpu = min(r[0] for r in runs), min(r[1] for r in runs)
    best = {k: [min(p[k][0] for p in parts), min(p[k][1] for p in parts)] for k in ("import", "run_scene", "write_run")}
    solve = min(p["solve_total_s"] for p in parts)
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")
    print("| phase | wall s | CPU s |\n|---|---|---|")
    print(f"| `vlab run --no-render --no-estimate` (whole command) | {wall:.2f} | {cpu:.2f} |")
    for name, (w, c) in best.items():
        print(f"| {name} | {w:.2f} | {c:.2f} |")
    print(f"| of run_scene: results.json timing.total_s | {solve:.2f} | — |")
    print(f"| overhead = command − timing.total_s | {wall - solve:.2f} | — |")


if __name__ == "__main__":
    main()
