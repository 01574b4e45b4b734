"""The direct/iterative crossover by the mesh's shape: whole runs on both linear paths, beside the
factorization's cost that PARDISO's analysis predicts (vlab.fe.iterative.decide).

    python benchmarks/linear_path.py [--problems octant,plate-thin,plate-thick,cube-24,cylinder]

Each (problem, path) runs in a fresh subprocess, imports, numba's start-up and MKL's loading before
the clock, with ``[solver] linear`` forced to "direct" (PARDISO, Cholesky stability checks) or
"cg-amg" (CG + AMG, LOBPCG stability checks). Printed per problem: free DOFs, the factorization
flops per stored entry of K_ff from PARDISO's analysis of K_ff itself and of the node graph
(what ``auto`` uses), the path ``auto`` takes, and each path's wall and CPU seconds.

Problems (compressible Neo-Hookean, μ = 0.4 MPa, K = 2 MPa, Q1 hexahedra, no extra levels for an
initial modulus): the sphere octant and the torsion cylinder of benchmarks/kinds_felupe.py
(inflation-50k, torsion-50k), two plates and the 24³ cube in uniaxial tension on roller grips to
stretch 1.5 in 10 steps.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

BLOCKS = {"plate-thin": ([60.0, 20.0, 6.0], 0.75), "plate-thick": ([30.0, 30.0, 10.0], 0.9),
          "cube-24": ([1.0, 1.0, 1.0], 1.0 / 24.0)}
PROBLEMS = {"octant": "inflation-50k", "plate-thin": None, "plate-thick": None, "cube-24": None,
            "cylinder": "torsion-50k"}


def scene(problem: str, linear: str = "auto"):
    """The problem's scene with ``[solver] linear`` set (module docstring)."""
    import dataclasses

    from vlab.scene import parse_scene

    if PROBLEMS[problem] is not None:
        import kinds_felupe

        sc = kinds_felupe.scene(PROBLEMS[problem])
        return dataclasses.replace(sc, solver=dataclasses.replace(sc.solver, linear=linear))
    size, h = BLOCKS[problem]
    return parse_scene({
        "name": problem, "specimen": {"shape": "block", "size": size},
        "mesh": {"size": h, "cell": "hex", "formulation": "displacement"},
        "material": {"model": "neo-hookean", "mu": 0.4, "K": 2.0},
        "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.5, "steps": 10},
        "measure": {"modulus_points": 0}, "solver": {"linear": linear}})


def predicted(problem: str) -> dict:
    """Free DOFs, flops per entry of K_ff (its own analysis, and the node graph's), auto's path."""
    import numpy as np
    import scipy.sparse as sp

    from vlab.fe.linsolve import factorization_cost
    from vlab.pipeline.prepare import prepare
    from vlab.pipeline.solve import _linear_path, _node_graph_cost

    prepared = prepare(scene(problem))
    part = prepared.partition
    n = len(part.free)
    Kff = sp.csr_matrix((np.ones(len(part.ff_indices)), part.ff_indices, part.ff_indptr), shape=(n, n))
    own = factorization_cost(Kff)
    nodes = _node_graph_cost(part)
    return {"free_dofs": n, "own": own.flops_per_nonzero if own else None,
            "node_graph": nodes.flops_per_nonzero if nodes else None, "auto": _linear_path(prepared).path}


def timed_run(problem: str, linear: str) -> dict:
    from vlab import jit, settings
    from vlab.fe import linsolve
    from vlab.run import run_scene

    sc = scene(problem, linear)
    linsolve.solver_in_use()
    jit.available(settings.current())
    t0, c0 = time.perf_counter(), time.process_time()
    result = run_scene(sc)
    return {"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0, "converged": result.converged,
            "path": result.diagnostics.linear_solver["newton"]}


def _subprocess(*args: str) -> dict:
    out = subprocess.run([sys.executable, __file__, *args], capture_output=True, text=True, check=False)
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("RESULT ")]
    if not lines:
        return {"error": out.stderr.strip().splitlines()[-1] if out.stderr.strip() else "no result"}
    return json.loads(lines[-1][len("RESULT "):])


def _row(problem: str) -> str:
    p = _subprocess("--predict", problem)
    runs = {path: _subprocess("--one", problem, path) for path in ("direct", "cg-amg")}
    cells = [f"{runs[k]['wall']:.1f} ({runs[k]['cpu']:.1f})" if "wall" in runs[k] else runs[k].get("error", "?")
             for k in ("direct", "cg-amg")]
    return (f"| {problem} | {p['free_dofs']:,} | {p['own']:,.0f} | {p['node_graph']:,.0f} | {p['auto']} | "
            f"{cells[0]} | {cells[1]} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--one", nargs=2, metavar=("PROBLEM", "LINEAR"), help=argparse.SUPPRESS)
    parser.add_argument("--predict", metavar="PROBLEM", help=argparse.SUPPRESS)
    parser.add_argument("--problems", default=",".join(PROBLEMS))
    args = parser.parse_args()
    if args.one:
        print("RESULT " + json.dumps(timed_run(*args.one)))
        return
    if args.predict:
        print("RESULT " + json.dumps(predicted(args.predict)))
        return
    for name in args.problems.split(","):
        if name not in PROBLEMS:
            parser.error(f"--problems: unknown problem {name!r}; allowed: {', '.join(PROBLEMS)}")
    print(f"load average {os.getloadavg()[0]:.1f} at the start\n")
    print("| problem | free DOFs | flops/entry, K_ff | flops/entry, node graph | auto | direct wall s (CPU s) | "
          "CG + AMG wall s (CPU s) |\n|---|---|---|---|---|---|---|", flush=True)
    for name in args.problems.split(","):
        print(_row(name), flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} at the end")


if __name__ == "__main__":
    main()
