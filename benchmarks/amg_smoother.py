"""The AMG smoother of vlab's iterative path, A/B on the cube benchmark (issue #20).

    python benchmarks/amg_smoother.py VARIANT N      # VARIANT: jacobi (shipped) | gs | cheb

Runs benchmarks/cube_scaling.py's vlab case (Neo-Hookean N³ cube, 10 steps to stretch 1.5) in
this process with vlab.fe.iterative.SMOOTHER set to damped Jacobi (the shipped default), pyamg's
default symmetric Gauss-Seidel, or Chebyshev of degree 3, and prints the run's figures. Below the
direct/iterative crossover set VLAB_ITERATIVE_FROM=1000 to take the iterative path. One variant a
process: run them one after another on a quiet machine (benchmarks/RESULTS.md, session 10).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import vlab  # noqa: E402  before numpy: numpy's BLAS serial, as in the CLI

vlab.serial_blas_process()

import cube_scaling  # noqa: E402
from vlab.fe import iterative  # noqa: E402

SMOOTHERS = {"jacobi": iterative.SMOOTHER,
             "gs": ("gauss_seidel", {"sweep": "symmetric"}),
             "cheb": ("chebyshev", {"degree": 3})}


def main() -> None:
    variant, n = sys.argv[1], int(sys.argv[2])
    iterative.SMOOTHER = SMOOTHERS[variant]
    r = cube_scaling.run_vlab(n)
    keys = ("total", "iterations", "amg_setups", "assembly", "linear", "stability_s", "force", "peak_mb")
    print(variant, n, json.dumps({k: r[k] for k in keys if k in r} if "error" not in r else r))


if __name__ == "__main__":
    main()
