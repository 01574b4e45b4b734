"""Direct vs iterative solves of one Newton system K_ff Δu = -r, to find where CG + AMG would win.

    python benchmarks/linear_solvers.py [--sizes 16,24,32] [--tol 1e-8]

For a Neo-Hookean cube of n × n × n Q1 hexahedra (1 mm), roller grips, stretched to 1.3 (a
realistic mid-test tangent), one process times on the same K_ff and right-hand side:

- PARDISO Cholesky: numerical factorization (analysis done once beforehand, as in a run) + solve;
- SuperLU (symmetric mode, as vlab uses it): factorization + solve;
- CG preconditioned by pyamg smoothed aggregation with the six rigid-body modes of the free DOFs
  as near-nullspace: setup + solve to a relative residual ``--tol`` and to 1e-3 (the forcing
  term an inexact Newton iteration needs early on).

Prints one row per size with DOFs, seconds and CG iteration counts (best of 2).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def system(n: int):
    from vlab.fe.assembly import Partition
    from vlab.fe.problem import HyperelasticBody
    from vlab.fe.space import DisplacementSpace
    from vlab.geometry.block import block_mesh
    from vlab.fe.iterative import rigid_body_modes
    from vlab.materials import make_material

    space = DisplacementSpace.build(block_mesh((n, n, n), 1.0, "hex"), 1)
    body = HyperelasticBody(space, make_material("neo-hookean", 5.77, 3.85))
    X = space.node_coordinates
    u = (X * np.array([0.3, -0.12, -0.12])).ravel()  # homogeneous stretch 1.3
    ev = body.evaluate(u)
    on = lambda axis, value: np.flatnonzero(np.abs(X[:, axis] - value) < 1e-9)  # noqa: E731
    prescribed = np.unique(np.r_[3 * on(0, 0.0), 3 * on(0, n), 3 * on(1, 0.0) + 1, 3 * on(2, 0.0) + 2])
    partition = Partition.build(body.pattern, prescribed)
    Kff = partition.blocks(body.stiffness(ev))[0]
    b = np.random.default_rng(0).standard_normal(Kff.shape[0])
    return Kff, b, rigid_body_modes(X)[partition.free]


def best(fn, repeat=2):
    out, t_best = None, np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        t_best = min(t_best, time.perf_counter() - t)
    return t_best, out


def cg_amg(K, b, B, tol):
    """vlab's own CG + AMG (setup + solve), as Newton uses it."""
    from vlab.fe.iterative import AMGConjugateGradient

    solver = AMGConjugateGradient(K, B)
    solver.solve(b, tol)
    return 0, solver.iterations[-1], None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="8,16,24,32")
    parser.add_argument("--tol", type=float, default=1e-8)
    args = parser.parse_args()
    from vlab.fe import linsolve, pardiso

    print(f"load average {os.getloadavg()[0]:.1f}")
    print("| n | free DOFs | PARDISO s | SuperLU s | CG+AMG s (tol) | its | CG+AMG s (1e-3) | its |")
    print("|---|---|---|---|---|---|---|---|")
    for n in map(int, args.sizes.split(",")):
        K, b, B = system(n)
        row = [str(n), str(K.shape[0])]
        if pardiso.library() is not None:
            linsolve.use_solver("pardiso")
            linsolve.factorize(K)  # analysis once
            row.append(f"{best(lambda: linsolve.factorize(K).solve(b))[0]:.2f}")
        else:
            row.append("-")
        linsolve.use_solver("superlu")
        row.append(f"{best(lambda: linsolve.factorize(K).solve(b), 1)[0]:.2f}" if K.shape[0] < 80000
                   else "-")
        linsolve.use_solver("auto")
        for tol in (args.tol, 1e-3):
            t, (info, its, res) = best(lambda: cg_amg(K, b, B, tol))
            row += [f"{t:.2f}" + ("" if info == 0 else " (no conv.)"), str(its)]
        print("| " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main()
