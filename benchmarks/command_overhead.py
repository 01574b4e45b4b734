"""What `vlab run SCENE --no-render --no-estimate` costs end to end, phase by phase.

    python benchmarks/command_overhead.py [SCENE] [--repeat 3]

Each repeat runs the real command (``python -m vlab run SCENE --no-render --no-estimate -q``) in a
fresh process, with clocks put around its phases from outside the package (vlab.run.run_scene,
vlab.report.writer.write_run and the final ``os._exit`` are wrapped by the launcher below, so the
command runs its own code): the interpreter's start-up, ``import vlab.cli`` (typer, rich, the scene
grammar and the registries it loads), the CLI until the solve, numba's start-up (inside run_scene,
before its clocks), the solve itself (results.json ``timing.total_s``: mesh, solve, measure), the
report without renders (results.json, CSV, PNGs, VTU/PVD, HTML) and the process exit. Wall seconds
and CPU seconds (user + system of all threads of the process; the figure process's CPU on its own
row). Three variants run interleaved, so that they meet the same load: the command as shipped (the
figures drawn by a second process started with the run, vlab.report.figure_worker; the fast exit of
vlab/__main__.py), with the figures drawn in process (VLAB_FIGURE_PROCESS=off), and with Python's
normal exit (interpreter finalization). Medians over the repeats. Each repeat also times the floor:
a process that only imports the libraries a run needs (numpy, scipy.sparse.linalg, scikit-fem,
typer, rich) and starts numba as vlab.jit does, then exits; the shipped overhead is printed above
that floor, the part vlab's own code can still change. Whether Python's bytecode cache is on is
printed (with PYTHONDONTWRITEBYTECODE=1 and no .pyc on disk, every run compiles vlab's ~130 modules
from source, ~0.3 s here). The load average is printed (the machine is shared: wall times under load are noisy, the CPU
figures are the steadier ones). ``--baseline TREE`` also times the plain command (``python -m vlab
run ...``, no launcher) with PYTHONPATH = TREE (e.g. a checkout of main) and with this tree,
interleaved (each from its own directory: ``-m`` puts the working directory first on the path):
whole-command wall and CPU and wall − timing.total_s; ``--plain-only`` skips the phase table.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VARIANTS = ("shipped", "in-process", "normal-exit")
LAUNCHER = r"""
import json, os, sys, time
def stamp():
    t = os.times()
    return [time.perf_counter(), t.user + t.system, t.children_user + t.children_system]
marks = {"start": stamp()}
variant, record, args = sys.argv[1], sys.argv[2], sys.argv[3:]
if variant == "in-process":
    os.environ["VLAB_FIGURE_PROCESS"] = "off"
import vlab.cli
marks["import_cli"] = stamp()
import vlab.report.writer, vlab.run
def wrapped(module, name, before, after):
    inner = getattr(module, name)
    def call(*a, **k):
        marks[before] = stamp()
        out = inner(*a, **k)
        marks[after] = stamp()
        if name == "run_scene":
            marks["solve_total_s"] = out.timing["total_s"]
        return out
    setattr(module, name, call)
wrapped(vlab.run, "run_scene", "run_start", "run_end")
wrapped(vlab.report.writer, "write_run", "write_start", "write_end")
def dump():
    marks["end"] = stamp()
    with open(record, "w") as f:
        json.dump(marks, f)
if variant == "normal-exit":
    try:
        vlab.cli.app(args=args, prog_name="vlab")
    except SystemExit as exc:
        dump()
        raise
else:
    real_exit = os._exit
    def fast_exit(code):
        dump()
        real_exit(code)
    os._exit = fast_exit
    sys.argv = ["vlab"] + args
    import vlab.__main__
    vlab.__main__.main()
"""


FLOOR = r"""
import os, sys, time
t = [time.perf_counter()]
import numpy, scipy.sparse.linalg, skfem, typer, rich
t.append(time.perf_counter())
import vlab.jit  # its own imports are the standard library's
vlab.jit.numba()  # import numba and make its first (cached) call, as vlab.run does
t.append(time.perf_counter())
print(" ".join(repr(x) for x in t))
sys.stdout.flush()
os._exit(0)
"""


def floor() -> list[float]:
    """[interpreter start-up, libraries, numba start-up, whole] wall seconds of a process that only
    imports the libraries a run needs (numpy, scipy.sparse.linalg, scikit-fem, typer, rich), starts
    numba as vlab.jit does, and ends with os._exit: what no change inside vlab can take off a
    fresh ``vlab run``."""
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", FLOOR], check=True, cwd=ROOT, capture_output=True, text=True)
    t1 = time.perf_counter()
    start, libraries, numba = (float(x) for x in out.stdout.split())
    return [start - t0, libraries - start, numba - libraries, t1 - t0]


def one(variant: str, scene: Path, out: Path, record: Path) -> dict:
    """Marks of one command (perf_counter is the system's monotonic clock, shared by processes)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", LAUNCHER, variant, str(record), "run", str(scene), "--no-render",
                    "--no-estimate", "--out", str(out), "-q", "--force"], check=True, cwd=ROOT,
                   capture_output=True)
    t1 = time.perf_counter()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    m = json.loads(record.read_text())
    total = m["solve_total_s"]

    def span(a, b):
        return [m[b][0] - m[a][0], m[b][1] - m[a][1]]

    run = span("run_start", "run_end")
    return {
        "interpreter start-up": [m["start"][0] - t0, m["start"][1]],
        "import vlab.cli (typer, rich, scene grammar, registries)": span("start", "import_cli"),
        "CLI until the solve (scene read, folder checks, vlab.run imports)": span("import_cli", "run_start"),
        "numba start-up (run_scene before its clocks)": [run[0] - total, None],
        "solve: results.json timing.total_s (mesh, solve, measure)": [total, None],
        "run_scene (numba start-up + solve), CPU of all threads": [run[0], run[1]],
        "report without renders (write_run)": span("write_start", "write_end"),
        "CLI after the report (summary)": span("write_end", "end"),
        "figure process (its CPU, beside the above)": [None, m["end"][2]],
        "process exit": [t1 - m["end"][0], cpu - m["end"][1] - m["end"][2]],
        "whole command": [t1 - t0, cpu],
        "overhead = whole command - timing.total_s": [t1 - t0 - total, None],
    }


def plain(tree: Path, scene: Path, out: Path) -> list[float]:
    """[wall, CPU, wall − timing.total_s] of the command run from ``tree``'s package."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "vlab", "run", str(scene), "--no-render", "--no-estimate", "--out",
                    str(out), "-q", "--force"], check=True, cwd=tree, capture_output=True,
                   env=os.environ | {"PYTHONPATH": str(tree)})  # cwd: `-m` puts it first on the path
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    total = json.loads((out / "results.json").read_text())["timing"]["total_s"]
    return [wall, cpu, wall - total]


def compare_trees(baseline: Path, scene: Path, repeat: int, scratch: Path) -> None:
    trees = {"baseline " + str(baseline): baseline, "this tree": ROOT}
    rows = {name: [] for name in trees}
    for i in range(repeat):
        for name, tree in trees.items():
            rows[name].append(plain(tree, scene, scratch / f"plain-{i}-{len(rows[name])}-{tree.name}"))
    print(f"\nplain command, median of {repeat} interleaved repeats; load average now {os.getloadavg()[0]:.1f}")
    print("| tree | whole command wall s | CPU s | wall − timing.total_s |\n|---|---|---|---|")
    for name, values in rows.items():
        print(f"| {name} | " + " | ".join(f"{statistics.median(v[j] for v in values):.2f}" for j in range(3)) + " |")


def median(rows: list[dict], key: str, i: int):
    values = [r[key][i] for r in rows if r[key][i] is not None]
    return statistics.median(values) if values else None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", nargs="?", default=str(ROOT / "benchmarks" / "block16.toml"))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--baseline", type=Path, default=None, help="another source tree to compare with")
    parser.add_argument("--plain-only", action="store_true", help="with --baseline: only the plain commands")
    args = parser.parse_args()
    if args.plain_only and args.baseline is not None:
        with tempfile.TemporaryDirectory() as scratch:
            compare_trees(args.baseline.resolve(), Path(args.scene), args.repeat, Path(scratch))
        return
    rows: dict[str, list[dict]] = {v: [] for v in VARIANTS}
    floors = []
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as scratch:
        for i in range(args.repeat):
            floors.append(floor())
            for v in VARIANTS:
                rows[v].append(one(v, Path(args.scene), Path(scratch) / f"{v}{i}", Path(scratch) / f"{v}{i}.json"))
    print(f"load average (1 min) at the start {load0:.1f}, at the end {os.getloadavg()[0]:.1f}; "
          f"median of {args.repeat} interleaved repeats; bytecode cache "
          f"{'OFF (PYTHONDONTWRITEBYTECODE: a module without a .pyc already on disk is compiled from source every run)' if sys.dont_write_bytecode else 'on'}")
    print("| phase | " + " | ".join(f"{v} wall s | {v} CPU s" for v in VARIANTS) + " |")
    print("|---|" + "---|---|" * len(VARIANTS))
    for key in rows[VARIANTS[0]][0]:
        cells = []
        for v in VARIANTS:
            for i in (0, 1):
                x = median(rows[v], key, i)
                cells.append("—" if x is None else f"{x:.2f}")
        print(f"| {key} | " + " | ".join(cells) + " |")
    print_floor(floors, median(rows[VARIANTS[0]], "overhead = whole command - timing.total_s", 0))
    if args.baseline is not None:
        with tempfile.TemporaryDirectory() as scratch:
            compare_trees(args.baseline.resolve(), Path(args.scene), args.repeat, Path(scratch))


def print_floor(floors: list[list[float]], overhead: float) -> None:
    """The floor's split and what the shipped command's overhead is above it."""
    m = [statistics.median(f[j] for f in floors) for j in range(4)]
    print("\nfloor: a process that imports the libraries a run needs, starts numba and exits (same repeats)")
    print("| interpreter start-up s | numpy, scipy.sparse.linalg, skfem, typer, rich s | numba start-up s "
          "| whole floor s | shipped overhead above the floor s |\n|---|---|---|---|---|")
    print(f"| {m[0]:.2f} | {m[1]:.2f} | {m[2]:.2f} | {m[3]:.2f} | {overhead - m[3]:.2f} |")


if __name__ == "__main__":
    main()
