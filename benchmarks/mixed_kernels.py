"""The mixed body's compiled kernels against its numpy kernels on Cook's membrane (ν = 0.4999).

    python benchmarks/mixed_kernels.py [--cook 64] [--repeat 3]

de Souza Neto's set-up (vlab/verification/cooks_membrane.py), Q1/P0 n × n, 10 dead-load steps,
rtol 1e-9. The two kernels run interleaved in one process (each warmed on 4 × 4 first: numba's
start-up and kernel loads are not timed); per repeat the whole solve's wall and CPU time (user +
system of all threads) and the condensed tangent's own time (MixedHyperelasticBody.stiffness,
wall and CPU, summed over the solve). Iterations, tip displacement and DOFs are deterministic; times on
the shared machine are not: the load average is printed, medians reported.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import vlab  # noqa: E402  numpy's BLAS serial, as in the CLI

vlab.serial_blas_process()

from vlab.fe.mixed import MixedHyperelasticBody  # noqa: E402
from vlab.verification.cooks_membrane import SOUZA_NETO, CookCase, solve_cook  # noqa: E402

KERNELS = ("numpy", "auto")
TANGENT: list[tuple[float, float]] = []  # (wall, CPU of all threads) of each condensed tangent
_stiffness = MixedHyperelasticBody.stiffness


def _timed_stiffness(self, evaluation):
    t0, c0 = time.perf_counter(), sum(os.times()[:2])
    K = _stiffness(self, evaluation)
    TANGENT.append((time.perf_counter() - t0, sum(os.times()[:2]) - c0))
    return K


MixedHyperelasticBody.stiffness = _timed_stiffness


def one(n: int, kernel: str) -> dict:
    TANGENT.clear()
    t0, c0 = time.perf_counter(), sum(os.times()[:2])
    result = solve_cook(CookCase(order=1, divisions=n, kernel=kernel, **SOUZA_NETO))
    return {"wall": time.perf_counter() - t0, "cpu": sum(os.times()[:2]) - c0, "tangent": sum(t[0] for t in TANGENT), "tangent_cpu": sum(t[1] for t in TANGENT),
            "tangents": len(TANGENT), "iterations": result.iterations, "per_step": result.per_step,
            "tip": result.tip_uy, "dofs": result.dofs}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cook", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    for kernel in KERNELS:
        one(4, kernel)
    load0 = os.getloadavg()[0]
    runs = {k: [] for k in KERNELS}
    for _ in range(args.repeat):
        for kernel in KERNELS:
            runs[kernel].append(one(args.cook, kernel))
    print(f"Cook's membrane Q1/P0 {args.cook}², ν = 0.4999, 10 steps; load average {load0:.1f} at the "
          f"start, {os.getloadavg()[0]:.1f} at the end; medians of {args.repeat} interleaved repeats")
    print("| kernels | DOFs | Newton iterations per step | total | tangents assembled | tip u_y (mm) "
          "| condensed tangent wall s (sum) | its CPU s | per tangent ms (wall) | solve wall s | solve CPU s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for kernel in KERNELS:
        r, med = runs[kernel][0], (lambda key: statistics.median(x[key] for x in runs[kernel]))
        name = "numpy" if kernel == "numpy" else "compiled"
        print(f"| {name} | {r['dofs']} | {', '.join(map(str, r['per_step']))} | {r['iterations']} | "
              f"{r['tangents']} | {r['tip']:.9f} | {med('tangent'):.2f} | {med('tangent_cpu'):.2f} | {1e3 * med('tangent') / r['tangents']:.1f} "
              f"| {med('wall'):.2f} | {med('cpu'):.2f} |")


if __name__ == "__main__":
    main()
