"""vlab against FElupe on torsion of a cylinder and inflation of a sphere-shell octant (issue #33).

    python benchmarks/kinds_felupe.py [--repeat N] [--problems torsion-small,inflation-small,...]
                                      [--out FILE.md]

Each measurement runs in a fresh subprocess (benchmarks/run.py's harness: ``--one CODE PROBLEM``),
imports, numba's start-up and the loading of PARDISO before the clock as there; the best of
``--repeat`` runs counts. Both codes get the very same nodes and hexahedra (vlab's mesh, exported
with run.py's ``felupe_hex_mesh``: DOF 3 i + c is the same DOF in both), the same material, the
same prescribed DOFs with the same values, the same number of equal steps (vlab with
``measure.modulus_points = 0``: no extra levels for an initial modulus), and stop at
‖r_free‖ / ‖r_prescribed‖ ≤ 1e-8.

Material (both kinds): compressible Neo-Hookean in the displacement formulation, Q1 hexahedra,
2 × 2 × 2 Gauss points, ψ = μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)² (vlab ``neo-hookean``, FElupe
``NeoHookeCompressible``) with μ = 0.4 MPa, K = 2 MPa (λ = K − 2μ/3, ν ≈ 0.41). The shipped
scenes specimens/cylinder-torsion.toml (Mooney–Rivlin) and specimens/sphere-inflation.toml
(K/μ = 1000) run the mixed Q1/P0 formulation, whose three-field FElupe counterpart is not the
same discretisation term by term; a moderately compressible law keeps both codes on one set of
discrete equations, which is what a 1e-6 comparison needs.

Torsion: specimens/cylinder-torsion.toml's cylinder (radius 5 mm, length 10 mm, along x), end x = 0
clamped, end x = L turned rigidly by φ = t ψ L with the length held (u_x = 0), ψ = 0.1 rad/mm,
10 steps. Readings at the end, from the turning end's nodes (reactions f, current positions x):
torque T = Σ (y f_z − z f_y) (N·mm), axial force N = Σ f_x (N).

Inflation: specimens/sphere-inflation.toml's octant (A = 10 mm, H = 1 mm), symmetry planes
holding the normal displacement, the inner surface driven radially, x = λ_a X, to λ_a = 2.5 in 30
steps: vlab's volume control, which on the symmetric octant is exactly a prescribed inner-surface
radial displacement, so FElupe gets that same displacement (not its pressure boundary, which
cannot pass the pressure maximum at λ_a ≈ 1.4). Reading at the end: the pressure
p = Σ f_i · X_i / (3 λ_a² V₀) over the inner nodes (MPa), V₀ the octant's facetted cavity volume.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from run import RTOL, _machine, _peak_mb, felupe_hex_mesh, interleaved_runs  # noqa: E402

import numpy as np  # noqa: E402

MU, K = 0.4, 2.0  # MPa
TWIST, TORSION_STEPS = 0.1, 10  # rad/mm, specimens/cylinder-torsion.toml
STRETCH, INFLATION_STEPS = 2.5, 30  # inner hoop stretch, specimens/sphere-inflation.toml
PROBLEMS = {  # name: (kind, element size mm)
    "torsion-small": ("torsion", 1.25),  # 3,915 DOFs (the shipped scene's size)
    "torsion-50k": ("torsion", 0.47),  # 54,717 DOFs
    "inflation-small": ("inflation", 0.75),  # 4,221 DOFs
    "inflation-50k": ("inflation", 0.25),  # 56,715 DOFs
}


def scene(problem: str):
    """The vlab scene of a problem (module docstring)."""
    from vlab.scene import parse_scene

    kind, h = PROBLEMS[problem]
    if kind == "torsion":
        specimen = {"shape": "cylinder", "radius": 5.0, "length": 10.0}
        test = {"kind": "torsion", "grips": "clamped", "axial": "fixed", "twist": TWIST,
                "steps": TORSION_STEPS}
    else:
        specimen = {"shape": "sphere-shell", "inner_radius": 10.0, "thickness": 1.0}
        test = {"kind": "inflation", "grips": "cavity", "control": "volume", "stretch": STRETCH,
                "steps": INFLATION_STEPS}
    return parse_scene({
        "name": f"bench-{problem}", "specimen": specimen,
        "mesh": {"size": h, "cell": "hex", "formulation": "displacement"},
        "material": {"model": "neo-hookean", "mu": MU, "K": K}, "test": test, "solver": {"rtol": RTOL},
        # the loading FElupe gets, nothing more: no extra small-strain levels for an initial modulus
        # (9 levels before the first step otherwise; benchmarks/run.py's cubes likewise)
        "measure": {"modulus_points": 0},
    })


def run_vlab(problem: str) -> dict:
    """vlab's run of the scene, timed warm; the readings at the last level."""
    from vlab import jit, settings
    from vlab.fe import linsolve
    from vlab.report.results import result_to_dict
    from vlab.run import run_scene

    sc = scene(problem)
    linsolve.solver_in_use()  # MKL's runtime, loaded untimed like FElupe's `import pypardiso`
    jit.available(settings.current())  # numba's start-up, untimed like the imports
    t0, c0 = time.perf_counter(), time.process_time()
    result = run_scene(sc)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    if not result.converged:
        return {"error": result.history.failure.reason}
    curve, data = result.curve, result_to_dict(result)
    timing, linear = data["timing"], data["solver"]["linear"]
    out = {"dofs": int(result.space.n_dofs), "wall": wall, "cpu": cpu,
           "iterations": int(sum(data["solver"]["newton_iterations"])),
           "factorizations": int(linear["factorizations"]), "amg_setups": int(linear["amg_setups"]),
           "path": linear["newton"], "assembly": timing["assembly_s"], "linear": timing["linear_solve_s"],
           "stability": timing.get("stability_check_s", 0.0), "peak_mb": _peak_mb()}
    if PROBLEMS[problem][0] == "torsion":
        out |= {"torque": float(curve.extra["torque"][-1]), "axial_force": float(curve.force[0][-1])}
    else:
        out |= {"pressure": float(curve.extra["pressure"][-1])}
    return out


def run_felupe(problem: str) -> dict:
    """FElupe on vlab's mesh with vlab's prescribed DOFs and values, equal steps (module docstring)."""
    import felupe as fem

    from vlab.loading.inflation import inflation_loading
    from vlab.loading.torsion import torsion_loading
    from vlab.run import build_specimen

    try:
        import pypardiso
        solver, solver_name = pypardiso.spsolve, "pypardiso"
    except ImportError:
        from scipy.sparse.linalg import spsolve as solver
        solver_name = "scipy spsolve"
    kind, _ = PROBLEMS[problem]
    sc = scene(problem)
    t0, c0 = time.perf_counter(), time.process_time()
    specimen = build_specimen(sc)
    mesh = felupe_hex_mesh(specimen.mesh)
    X = mesh.points
    if kind == "torsion":
        loading = torsion_loading(specimen, X, TWIST, "fixed")
        steps = TORSION_STEPS
        values = [loading.path(k / steps) for k in range(1, steps + 1)]
    else:
        loading = inflation_loading(specimen, X, STRETCH)
        steps = INFLATION_STEPS
        values = [loading.u_hat * (k / steps) for k in range(1, steps + 1)]
    region = fem.RegionHexahedron(mesh)
    field = fem.FieldContainer([fem.Field(region, dim=3)])
    solid = fem.SolidBody(fem.NeoHookeCompressible(mu=MU, lmbda=K - 2.0 * MU / 3.0), field)
    mask = np.zeros(3 * len(X), dtype=bool)
    mask[loading.prescribed] = True
    grips = fem.Boundary(field[0], mask=mask.reshape(-1, 3))
    dof0, dof1 = fem.dof.partition(field, {"grips": grips})
    newton = getattr(fem, "newtonraphson", None) or fem.newtonrhapson  # spelt so before FElupe 10.2
    iterations = 0
    for k, u_p in enumerate(values, start=1):  # the loop of FElupe's Step, written out (Job's callback is deprecated in 11.3)
        grips.update(u_p[grips.dof])  # grips.dof: 3 i + c, ascending
        ext0 = fem.dof.apply(field, {"grips": grips}, dof0)
        res = newton(items=[solid], x0=field, dof0=dof0, dof1=dof1, ext0=ext0, tol=RTOL,
                     solver=solver, verbose=0)
        if not res.success:
            return {"error": f"FElupe's Newton did not converge at step {k} of {steps}"}
        field.link(res.x)
        iterations += res.iterations
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    f = solid.assemble.vector(field).toarray().ravel()
    u = field[0].values.ravel()
    nodes = loading.moving_dofs[0] // 3
    out = {"dofs": int(u.size), "wall": wall, "cpu": cpu, "levels": steps,
           "iterations": int(iterations), "solver": solver_name, "peak_mb": _peak_mb()}
    if kind == "torsion":
        y, z = X[nodes, 1] + u[3 * nodes + 1], X[nodes, 2] + u[3 * nodes + 2]
        out |= {"torque": float(np.sum(y * f[3 * nodes + 2] - z * f[3 * nodes + 1])),
                "axial_force": float(np.sum(f[3 * nodes]))}
    else:
        Xi = X[nodes]
        lam = float(np.mean(np.linalg.norm(Xi + u.reshape(-1, 3)[nodes], axis=1) / np.linalg.norm(Xi, axis=1)))
        work = float(np.sum(f.reshape(-1, 3)[nodes] * Xi))
        out |= {"pressure": work / (3.0 * lam * lam * specimen.area0[0])}
    return out


READINGS = ("torque", "axial_force", "pressure")


def compare(v: dict, f: dict) -> dict:
    """|vlab − FElupe| / |FElupe| of each reading both report."""
    return {k: abs(v[k] - f[k]) / abs(f[k]) for k in READINGS if k in v and k in f}


def _table(rows) -> str:
    head = ("| problem | DOFs | vlab wall s | vlab CPU s | FElupe wall s | FElupe CPU s | vlab/FElupe wall | vlab/FElupe CPU | "
            "Newton it. vlab / FElupe | vlab linear path, factorizations, AMG setups | vlab assembly / linear / stability s | "
            "reading: vlab, FElupe | rel. diff |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for name, v, f in rows:
        if "error" in v or "error" in f:
            lines.append(f"| {name} | vlab: {v.get('error', 'ok')}; FElupe: {f.get('error', 'ok')} |")
            continue
        diff = compare(v, f)
        readings = "; ".join(f"{k} {v[k]:.8g}, {f[k]:.8g}" for k in diff)
        lines.append(
            f"| {name} | {v['dofs']} | {v['wall']:.2f} | {v['cpu']:.2f} | {f['wall']:.2f} | {f['cpu']:.2f} | "
            f"{v['wall'] / f['wall']:.2f} | {v['cpu'] / f['cpu']:.2f} | {v['iterations']} / {f['iterations']} | "
            f"{v['path']}, {v['factorizations']}, {v['amg_setups']} | "
            f"{v['assembly']:.2f} / {v['linear']:.2f} / {v['stability']:.2f} | {readings} | "
            + ", ".join(f"{d:.1e}" for d in diff.values()) + " |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--one", nargs=2, metavar=("CODE", "PROBLEM"), help=argparse.SUPPRESS)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--problems", default="torsion-small,inflation-small")
    parser.add_argument("--out", type=Path, default=None, help="append the table to this Markdown file")
    args = parser.parse_args()
    if args.one:
        code, problem = args.one
        print("RESULT " + json.dumps(run_vlab(problem) if code == "vlab" else run_felupe(problem)))
        return
    for name in args.problems.split(","):
        if name not in PROBLEMS:
            parser.error(f"--problems: unknown problem {name!r}; allowed: {', '.join(PROBLEMS)}")
    machine = _machine()
    rows = []
    for problem in args.problems.split(","):
        runs = interleaved_runs(problem, args.repeat, __file__)
        best = {code: min((r for r in rs if "error" not in r), key=lambda r: r["wall"], default=rs[-1])
                for code, rs in runs.items()}
        rows.append((problem, best["vlab"], best["felupe"]))
        print(f"{problem}: vlab {best['vlab']}\n  FElupe {best['felupe']}", flush=True)
    table = _table(rows)
    print(f"\nMachine: {machine}; load average {os.getloadavg()[0]:.1f} at the end\n\n{table}")
    if args.out:
        with args.out.open("a", encoding="utf-8") as out:
            out.write(f"\nCommand: `python benchmarks/kinds_felupe.py {' '.join(sys.argv[1:])}`\n\n"
                      f"Machine: {machine}; load average {os.getloadavg()[0]:.1f} at the end\n\n{table}\n")


if __name__ == "__main__":
    main()
