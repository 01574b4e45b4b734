"""Near-incompressible Newton: vlab's mixed Q1/P0 against FElupe's, same meshes, loads, law.

    python benchmarks/near_incompressible.py [--cook 64] [--block 8] [--repeat 2]

Problems (ν = 0.4999, 10 equal dead-load steps, ‖r_free‖ / ‖r_prescribed‖ ≤ 1e-9 (vlab) and
FElupe's relative residual norm ≤ 1e-9):
* Cook's membrane, de Souza Neto's set-up (vlab/verification/cooks_membrane.py: G = 80.194 MPa,
  100 N over the right edge, plane strain, one element thick), n × n Q1/P0;
* deal.II step-44's block (vlab/verification/step44_block.py), n³ Q1/P0 on the quarter.
Both codes get the same nodes, hexahedra (VTK order for FElupe) and nodal forces (vlab's
consistent ones, as a FElupe PointLoad), and the same energy: FElupe's isochoric NeoHooke
(ψ = ½μ(J^(−2/3) I₁ − 3)) in NearlyIncompressible with U = ¼K(J̄² − 1 − 2 ln J̄) (its dUdJ,
d2UdJdJ), i.e. vlab's SplitNeoHookean. FElupe: FieldsMixed(n=3) (u, p, J̄; Newton on all
three, condensed), PARDISO. vlab: "three-field" (θ carried by its Newton update; the default)
and "reduced" (θ = Π_e v(F) recomputed at every iterate: the formulation before issue 20).
The runs of each repeat are interleaved (vlab three-field, vlab reduced, FElupe); the best of
the repeats is reported, with its wall and CPU time (user + system of all threads: PARDISO runs
2 threads for both codes). The machine is shared: times are noisy, iterations are not.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import vlab  # noqa: E402,F401  numpy's BLAS serial, as in the CLI
import numpy as np  # noqa: E402

from vlab.fe.assembly import Partition  # noqa: E402
from vlab.fe.mixed import MixedHyperelasticBody  # noqa: E402
from vlab.fe.newton import NewtonOptions  # noqa: E402
from vlab.fe.space import DisplacementSpace  # noqa: E402
from vlab.materials.split import SplitNeoHookean  # noqa: E402
from vlab.moduli import from_pair  # noqa: E402
from vlab.verification import cooks_membrane as cook  # noqa: E402
from vlab.verification import step44_block as block  # noqa: E402
from vlab.verification.dead_load import ramp  # noqa: E402

RTOL, STEPS = 1e-9, 10


def cook_problem(n: int, three_field: bool):
    """(body, partition, f_total, point of interest, length) of Cook's membrane (de Souza Neto)."""
    moduli = from_pair({"mu": cook.SOUZA_NETO["mu"], "nu": cook.SOUZA_NETO["nu"]})
    space = DisplacementSpace.build(cook.membrane_mesh(n), 1)
    body = MixedHyperelasticBody(space, SplitNeoHookean(moduli.lmbda, moduli.mu), three_field)
    X = space.node_coordinates
    clamped = np.flatnonzero(np.isclose(X[:, 0], 0.0))
    prescribed = np.unique(np.concatenate([(3 * clamped[:, None] + np.arange(3)).ravel(),
                                           3 * np.arange(len(X)) + 2]))
    tip = int(np.flatnonzero(np.hypot(X[:, 0] - 48.0, X[:, 1] - 60.0) < 1e-9)[0])
    return (body, Partition.build(body.pattern, prescribed),
            cook.edge_traction(space, cook.SOUZA_NETO["traction"]), 3 * tip + 1, 48.0)


def step44_problem(n: int, three_field: bool):
    body, partition, f, centre = block.block_problem(n, three_field)
    return body, partition, f, 3 * centre + 1, 1.0


def _cpu() -> float:
    t = os.times()
    return t.user + t.system


def run_vlab(problem, n: int, three_field: bool) -> dict:
    t0, c0 = time.perf_counter(), _cpu()
    body, partition, f, dof, length = problem(n, three_field)
    result = ramp(body, partition, f, STEPS, NewtonOptions(rtol=RTOL, max_iterations=30), length)
    return {"dofs": body.space.n_dofs, "per_step": result.per_step, "iterations": result.iterations,
            "cutbacks": len(result.failed), "value": float(result.u[dof]), "seconds": time.perf_counter() - t0,
            "cpu": _cpu() - c0, "failure": result.failure}


def _felupe_hexes(space: DisplacementSpace):
    """The space's nodes and hexahedra in FElupe's (VTK) corner order, by scikit-fem's own
    meshio conversion (as benchmarks/run.py does for the dogbone)."""
    from skfem.io.meshio import to_meshio

    m = to_meshio(space.basis.mesh)
    return m.points.copy(), m.cells_dict["hexahedron"].copy()


def run_felupe(problem, n: int) -> dict:
    import felupe as fem
    import pypardiso

    t0, c0 = time.perf_counter(), _cpu()
    body, partition, f, dof, _ = problem(n, True)
    points, cells = _felupe_hexes(body.space)
    mesh = fem.Mesh(points, cells, "hexahedron")
    field = fem.FieldsMixed(fem.RegionHexahedron(mesh), n=3)
    law = body.material
    umat = fem.NearlyIncompressible(fem.NeoHooke(mu=law.mu), bulk=law.kappa,
                                    dUdJ=lambda J, K: 0.5 * K * (J - 1.0 / J),
                                    d2UdJdJ=lambda J, K: 0.5 * K * (1.0 + 1.0 / J**2))
    solid = fem.SolidBody(umat, field)
    fixed = np.zeros(points.shape, dtype=bool).ravel()
    fixed[partition.prescribed] = True
    bounds = {"fixed": fem.Boundary(field[0], mask=fixed.reshape(-1, 3))}  # (node, component) mask
    loaded = np.flatnonzero(np.any(f.reshape(-1, 3) != 0.0, axis=1))
    forces = f.reshape(-1, 3)[loaded]
    load = fem.PointLoad(field, loaded, forces)
    iterations = []
    ramped = np.array([t * forces for t in np.arange(1, STEPS + 1) / STEPS])  # PointLoad.update(values)
    step = fem.Step(items=[solid, load], ramp={load: ramped}, boundaries=bounds)
    job = fem.Job([step], plugins=[lambda context, state: iterations.append(context.substep.iterations)])
    job.evaluate(tol=RTOL, solver=pypardiso.spsolve, verbose=0)
    value = float(field[0].values.ravel()[dof])
    return {"dofs": int(field[0].values.size), "per_step": iterations, "iterations": int(sum(iterations)),
            "cutbacks": 0, "value": value, "seconds": time.perf_counter() - t0, "cpu": _cpu() - c0,
            "failure": ""}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cook", type=int, default=64)
    parser.add_argument("--block", type=int, default=8)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    problems = [(f"Cook's membrane Q1/P0 {args.cook}²", cook_problem, args.cook, "tip u_y"),
                (f"step-44 block Q1/P0 {args.block}³", step44_problem, args.block, "u_y top centre")]
    # before the clocks: imports, numba's start-up and vlab's compiled kernels (the compiled
    # inverse needs ≥ 256 quadrature points: 8² Cook and 4³ block have 512)
    for problem, n in ((cook_problem, 8), (step44_problem, 4)):
        run_vlab(problem, n, True), run_felupe(problem, n)
    print("| problem | code | DOFs | Newton iterations per step | total | cutbacks | value (mm) "
          "| time s (wall, under load) | CPU s (all threads) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, problem, n, quantity in problems:
        best: dict[str, dict] = {}
        for _ in range(args.repeat):
            for code, run in (("vlab three-field", lambda: run_vlab(problem, n, True)),
                              ("vlab reduced", lambda: run_vlab(problem, n, False)),
                              ("FElupe + PARDISO", lambda: run_felupe(problem, n))):
                out = run()
                if code not in best or out["seconds"] < best[code]["seconds"]:
                    best[code] = out
        for code, out in best.items():
            steps = ", ".join(map(str, out["per_step"]))
            print(f"| {name} ({quantity}) | {code} | {out['dofs']} | {steps} | {out['iterations']} | "
                  f"{out['cutbacks']} | {out['value']:.9g} | {out['seconds']:.2f} | {out['cpu']:.2f} |"
                  f"{' ' + out['failure'] if out['failure'] else ''}")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
