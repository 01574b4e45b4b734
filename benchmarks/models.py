"""The rubber models on the 16³ benchmark block against Neo-Hookean: Newton iterations,
factorizations and wall time, interleaved in one process.

    python benchmarks/models.py [--rounds 3] [--scene benchmarks/block16.toml] [--models neo-hookean,ogden]

Every model gets the small-strain constants of the benchmark's Neo-Hookean (E = 10 MPa, ν = 0.3:
μ0 = 3.846 MPa, K = 8.333 MPa) through its own card (below) and runs the same mesh (16 × 16 × 16
Q1 hexahedra, 14,739 DOFs), roller grips, stretch 1.5 in 10 steps, rtol 1e-8. The rounds
interleave the models (NH, MR, Yeoh, Ogden, Gent, AB, NH, MR, ...) so that machine load hits
them alike; the best wall time per model counts, iterations and factorizations are
deterministic. The first round is a warm-up (numba compiles and caches kernels) and is dropped.
Printed: the best and the median wall time per model and the median CPU time (all threads of
the process: steadier than wall time on a shared machine), each with its ratio to Neo-Hookean's.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import vlab  # noqa: E402  before numpy, as in the CLI

vlab.serial_blas_process()  # numpy's BLAS serial (import vlab no longer sets it)

MU0, K = 10.0 / 2.6, 10.0 / (3 * 0.4)
AB_FACTOR = 1 + 3 / 45 + 99 / (175 * 81) + 513 / (875 * 729) + 42039 / (67375 * 6561)  # λm = 3
CARDS = {
    "neo-hookean": None,  # the benchmark scene's own [material]
    "mooney-rivlin": {"model": "mooney-rivlin", "C10": 0.375 * MU0, "C01": 0.125 * MU0, "K": K},
    "yeoh": {"model": "yeoh", "C10": MU0 / 2, "C20": -0.02 * MU0, "C30": 0.002 * MU0, "K": K},
    "ogden": {"model": "ogden", "mu": [m * MU0 / 0.6212 for m in (0.63, 0.0012, -0.01)],
              "alpha": [1.3, 5.0, -2.0], "K": K},
    "gent": {"model": "gent", "mu": MU0, "Jm": 20.0, "K": K},
    "arruda-boyce": {"model": "arruda-boyce", "mu": MU0 / AB_FACTOR, "lambda_m": 3.0, "K": K},
}


def scene_for(base, model: str):
    from vlab.scene import parse_scene

    raw = dict(base.source)
    if CARDS[model] is not None:
        raw["material"] = CARDS[model]
    return parse_scene(raw)


def one(scene) -> dict:
    from vlab.run import run_scene

    t0, c0 = time.perf_counter(), time.process_time()
    result = run_scene(scene)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    h = result.history
    return {"wall": wall, "cpu": cpu, "converged": result.converged,
            "iterations": int(sum(lv.iterations for lv in h.levels)),
            "factorizations": h.factorizations,
            "kernel": result.diagnostics.tangent_kernel,
            "error": (result.reference or {}).get("max_relative_error_x")}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--scene", default=str(ROOT / "benchmarks" / "block16.toml"))
    ap.add_argument("--models", default=",".join(CARDS), help="comma-separated, neo-hookean first")
    args = ap.parse_args()
    models = args.models.split(",")
    from vlab.scene import load_scene

    base = load_scene(args.scene)
    scenes = {m: scene_for(base, m) for m in models}
    runs: dict[str, list[dict]] = {m: [] for m in models}
    load = []
    for r in range(args.rounds + 1):
        for m, scene in scenes.items():
            out = one(scene)
            if r > 0:
                runs[m].append(out)
        load.append(os.getloadavg()[0])
    nh = min(x["wall"] for x in runs["neo-hookean"])
    nh_median = statistics.median(x["wall"] for x in runs["neo-hookean"])
    nh_cpu = statistics.median(x["cpu"] for x in runs["neo-hookean"])
    print(f"load average (1 min) after each round: {', '.join(f'{v:.2f}' for v in load)}")
    print(f"| model | Newton iterations | factorizations | wall s best of {args.rounds} | × NH | "
          "wall s median | × NH (medians) | CPU s median | × NH (CPU) | tangent kernel | "
          "max rel. error vs analytic |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |")
    for m, xs in runs.items():
        best = min(x["wall"] for x in xs)
        median = statistics.median(x["wall"] for x in xs)
        cpu = statistics.median(x["cpu"] for x in xs)
        x = xs[0]
        print(f"| {m} | {x['iterations']} | {x['factorizations']} | {best:.2f} | {best / nh:.2f} | "
              f"{median:.2f} | {median / nh_median:.2f} | {cpu:.2f} | {cpu / nh_cpu:.2f} | "
              f"{x['kernel']} | {x['error']:.1e} |")


if __name__ == "__main__":
    main()
