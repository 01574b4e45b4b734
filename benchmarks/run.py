"""vlab against its cost floor and against FElupe, on the same meshes, material, steps, tolerance.

    python benchmarks/run.py [--repeat N] [--problems block8,block16,...] [--newton reuse|exact]
                             [--out benchmarks/RESULTS.md]

Each measurement runs in a fresh subprocess (``--one CODE PROBLEM``) so that peak memory
(ru_maxrss) belongs to one run and imports are paid equally; the best of ``--repeat`` runs counts.

Problem: a Neo-Hookean cube (E = 10 MPa, ν = 0.3) of n × n × n mm meshed at 1 mm (Q1 hex, P1
tets: each hex split into tets as scikit-fem does) or at 2 mm (P2 tets), stretched to 1.5 in 10
equal displacement steps between roller grips: u_x = 0 on x = 0, u_x = 0.5 n on x = n, plus
u_y = u_z = 0 at the origin and u_z = 0 at (0, n, 0). Both codes get the very same nodes and
elements, and stop at ‖r_free‖ / ‖r_prescribed‖ ≤ 1e-8.

Dogbone: ISO 527-2 1BA, Q1 hexahedra of 0.6 mm (21,285 DOFs), clamped grips (every component of
the grip nodes prescribed, the moving grip's x travel ramped), same material, steps, tolerance.

The floor is measured inside every vlab subprocess at its final state (best of 7; the lowest over
the runs is used): one tangent assembly (vlab's kernel), one sparse Cholesky numerical
factorization (PARDISO, analysis reused; SuperLU if PARDISO is absent) and one solve. The issue's
floor ("floor/it") is that per-iteration cost times the Newton iterations of the test, i.e. of a
plain Newton that assembles and factorizes every iteration: FElupe's count in the same run (30 on
every problem here). The stricter "floor" counts only the factorizations vlab made (Newton
iterations that refactorize, the stability check of every converged state, whose factor also
serves the next predictor and the chord steps after it, and the unloaded tangent). Iterations
that reuse a factor (chord steps) are in vlab's iteration count but cost no factorization;
"exact" counts the ones that factorize. ``--newton exact`` runs vlab with ``solver.newton =
"exact"`` (refactorize every iteration after the first chord step) instead of the default reuse.

vlab evaluates F and the internal force and assembles the tangent with its compiled kernels
(numba, vlab/fe/compiled.py), the tangent in numba's threads (2 here: slabs of elements that
share no node), unless the environment says ``VLAB_KERNEL=numpy`` (``VLAB_ASSEMBLY_THREADS=1``:
one thread). FElupe runs with its defaults. numba's one-time start-up (~0.3 s) is paid when
vlab's modules are imported, before the clock starts, like every other import of either code,
and so is the loading of each code's PARDISO library (FElupe: ``import pypardiso``; vlab's
binding loads MKL's runtime on first use, ~19 ms, so the harness asks for it before the clock);
loading vlab's cached kernels (~20 ms) is in the timed run. Peak memory includes numba's compiler
(~100 MB). vlab's mesher numbers nodes and elements along the longest extent (z for a cube);
FElupe gets the same nodes and elements.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import vlab  # noqa: E402  before numpy, as in the CLI: numpy's BLAS serial (vlab/__init__.py)

vlab.serial_blas_process()
import numpy as np  # noqa: E402

E, NU, STRETCH, STEPS, RTOL = 10.0, 0.3, 1.5, 10, 1e-8
NEWTON = os.environ.get("VLAB_BENCH_NEWTON", "reuse")  # solver.newton of the vlab runs (--newton)
PROBLEMS = {  # name: (cell, order, cube edge n in mm, element size in mm)
    "block8-hex": ("hex", 1, 8.0, 1.0),
    "block16-hex": ("hex", 1, 16.0, 1.0),
    "block24-hex": ("hex", 1, 24.0, 1.0),
    "block16-tet-p1": ("tet", 1, 16.0, 1.0),
    "block16-tet-p2": ("tet", 2, 16.0, 2.0),
    "dogbone-hex": ("hex", 1, None, 0.6),  # ISO 527-2 1BA, clamped grips, 21,285 DOFs
}
DOGBONE = "ISO 527-2 1BA"


def _scene(problem: str):
    from vlab.scene import parse_scene

    cell, order, n, h = PROBLEMS[problem]
    if n is None:
        return parse_scene({
            "name": f"bench-{problem}",
            "specimen": {"shape": "dogbone", "standard": DOGBONE},
            "mesh": {"size": h, "order": order, "cell": cell},
            "material": {"model": "neo-hookean", "E": E, "nu": NU},
            "test": {"kind": "uniaxial", "grips": "clamped", "stretch": STRETCH, "steps": STEPS},
            "measure": {"modulus_points": 0},
            "solver": {"rtol": RTOL, "newton": NEWTON},
        })
    return parse_scene({
        "name": f"bench-{problem}",
        "specimen": {"shape": "block", "size": [n, n, n]},
        "mesh": {"size": h, "order": order, "cell": cell},
        "material": {"model": "neo-hookean", "E": E, "nu": NU},
        "test": {"kind": "uniaxial", "grips": "roller", "stretch": STRETCH, "steps": STEPS},
        "measure": {"modulus_points": 0},
        "solver": {"rtol": RTOL, "newton": NEWTON},
    })


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


class _Clock:
    """Accumulates wall time of wrapped functions by category."""

    def __init__(self):
        self.seconds: dict[str, float] = {"assembly": 0.0, "factorization": 0.0, "solve": 0.0}

    def wrap(self, owner, name: str, category: str) -> None:
        original = getattr(owner, name)

        def timed(*args, **kwargs):
            t = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                self.seconds[category] += time.perf_counter() - t

        setattr(owner, name, timed)


def run_vlab(problem: str) -> dict:
    from vlab import jit, settings
    from vlab.fe import linsolve, newton, problem as fe_problem, tangents
    from vlab.run import run_scene

    clock = _Clock()
    clock.wrap(fe_problem.HyperelasticBody, "stiffness", "assembly")
    clock.wrap(newton, "factorize", "factorization")
    clock.wrap(tangents, "factorize", "factorization")  # the converged states' (tangent cache)
    for cls in (linsolve.PardisoFactorization, linsolve.SuperLUFactorization):
        clock.wrap(cls, "solve", "solve")
    scene = _scene(problem)
    linsolve.solver_in_use()  # loads MKL's runtime, as FElupe's `import pypardiso` does untimed
    jit.available(settings.current())  # numba's start-up, untimed like FElupe's imports (no vlab import starts it)
    t0 = time.perf_counter()
    result = run_scene(scene)
    total = time.perf_counter() - t0
    if not result.converged:
        return {"error": result.history.failure.reason}
    iterations = sum(level.iterations for level in result.history.levels)
    out = {"dofs": int(result.space.n_dofs), "iterations": int(iterations), "total": total,
           "newton": scene.solver.newton,
           "factorizations": int(result.history.factorizations),
           "kernel": result.diagnostics.tangent_kernel,
           "force": float(result.curve.force[0][-1]), "solver": linsolve.solver_in_use(),
           **clock.seconds}
    out["other"] = total - sum(clock.seconds.values())
    out["exact_iterations"] = int(sum(r.exact for level in result.history.levels
                                      for r in level.newton))
    out["floor_per_iteration"] = _floor(result)
    out["floor"] = out["floor_per_iteration"] * out["factorizations"]
    out["peak_mb"] = _peak_mb()
    return out


def _floor(result) -> float:
    """Best of 7: one tangent assembly + Cholesky numerical factorization + solve at the end state."""
    from vlab.fe.assembly import Partition
    from vlab.fe.linsolve import factorize
    from vlab.fe.problem import HyperelasticBody
    from vlab.loading.grips import grip_loading
    from vlab.materials import make_material

    scene = result.scene
    material = make_material(scene.material.model, scene.material.moduli.lmbda, scene.material.moduli.mu)
    body = HyperelasticBody(result.space, material)
    loading = grip_loading(result.specimen, result.space.node_coordinates, scene.test.stretch,
                           scene.test.grips)
    partition = Partition.build(body.pattern, loading.prescribed)
    ev = body.evaluate(result.final_displacement)
    factorize(partition.blocks(body.stiffness(ev))[0])  # analysis once, as in the run
    best = np.inf
    for _ in range(7):
        t = time.perf_counter()
        Kff, _ = partition.blocks(body.stiffness(ev))
        factorize(Kff).solve(ev.f_int[partition.free])
        best = min(best, time.perf_counter() - t)
    return best


def _felupe_mesh(problem: str):
    """vlab's own mesh (same nodes, same elements) in FElupe's cell conventions."""
    import felupe as fem

    from vlab.geometry.block import block_mesh

    cell, order, n, h = PROBLEMS[problem]
    if n is None:  # the dogbone
        from vlab.run import build_specimen

        return felupe_hex_mesh(build_specimen(_scene(problem)).mesh)
    mesh = block_mesh((n, n, n), h, cell)
    points, cells = mesh.p.T.copy(), mesh.t.T.copy()
    if cell == "hex":
        # VTK order: corner bits (x, y, z) -> 0,1,3,2,4,5,7,6
        local = points[cells] - points[cells].min(axis=1, keepdims=True)
        bits = (local > 1e-9 * n).astype(int) @ np.array([1, 2, 4])
        vtk = np.array([0, 1, 3, 2, 4, 5, 7, 6])[bits]
        ordered = np.empty_like(cells)
        np.put_along_axis(ordered, vtk, cells, axis=1)  # ordered[e, vtk[e, j]] = cells[e, j]
        return fem.Mesh(points, ordered, "hexahedron")
    x = points[cells]
    volume = np.einsum("ej,ej->e", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), x[:, 3] - x[:, 0])
    cells[volume < 0] = cells[volume < 0][:, [0, 2, 1, 3]]
    tets = fem.Mesh(points, cells, "tetra")
    return tets if order == 1 else fem.mesh.add_midpoints_edges(tets)


def felupe_hex_mesh(mesh):
    """A scikit-fem Q1 hexahedral mesh as a FElupe mesh: the same nodes in the same order (so a
    DOF 3 i + c is the same in both codes), the cells in VTK order by scikit-fem's own conversion."""
    import felupe as fem
    from skfem.io.meshio import to_meshio

    m = to_meshio(mesh)
    return fem.Mesh(m.points.copy(), m.cells_dict["hexahedron"].copy(), "hexahedron")


def run_felupe(problem: str) -> dict:
    import felupe as fem

    try:
        import pypardiso
        solver, solver_name = pypardiso.spsolve, "pypardiso"
    except ImportError:
        from scipy.sparse.linalg import spsolve as solver
        solver_name = "scipy spsolve"
    cell, order, n, _ = PROBLEMS[problem]
    lmbda = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    t0 = time.perf_counter()
    mesh = _felupe_mesh(problem)
    region = {("hex", 1): fem.RegionHexahedron, ("tet", 1): fem.RegionTetra,
              ("tet", 2): fem.RegionQuadraticTetra}[(cell, order)](mesh)
    field = fem.FieldContainer([fem.Field(region, dim=3)])
    solid = fem.SolidBody(fem.NeoHookeCompressible(mu=mu, lmbda=lmbda), field)
    X = mesh.points
    u = field[0]
    if n is None:
        bounds, moving, travel = _felupe_clamps(problem, u, X)
    else:
        tol = 1e-9 * n
        at = lambda p: np.all(np.abs(X - p) <= tol, axis=1)  # noqa: E731
        bounds = {
            "fixed": fem.Boundary(u, mask=np.abs(X[:, 0]) <= tol, skip=(0, 1, 1)),
            "move": fem.Boundary(u, mask=np.abs(X[:, 0] - n) <= tol, skip=(0, 1, 1)),
            "origin": fem.Boundary(u, mask=at([0, 0, 0]), skip=(1, 0, 0)),
            "side": fem.Boundary(u, mask=at([0, n, 0]), skip=(1, 1, 0)),
        }
        moving, travel = np.flatnonzero(np.abs(X[:, 0] - n) <= tol), (STRETCH - 1) * n
    iterations = []
    step = fem.Step(items=[solid], ramp={bounds["move"]: travel * np.arange(1, STEPS + 1) / STEPS},
                    boundaries=bounds)
    job = fem.Job([step], callback=lambda i, j, res, **kw: iterations.append(res.iterations))
    job.evaluate(tol=RTOL, solver=solver, verbose=0)
    total = time.perf_counter() - t0
    r = solid.assemble.vector(field).toarray().ravel()
    return {"dofs": int(field[0].values.size), "iterations": int(sum(iterations)), "total": total,
            "force": float(np.sum(r[3 * moving])), "solver": solver_name, "peak_mb": _peak_mb()}


def _felupe_clamps(problem: str, u, X: np.ndarray):
    """vlab's clamped grips as FElupe boundaries: all components of the grip nodes, the moving
    grip's x component ramped (the very DOFs and travel vlab prescribes)."""
    import felupe as fem

    from vlab.loading.grips import grip_loading
    from vlab.run import build_specimen

    scene = _scene(problem)
    specimen = build_specimen(scene)
    loading = grip_loading(specimen, X, scene.test.stretch, scene.test.grips)
    clamped = np.zeros(len(X), dtype=bool)
    clamped[loading.prescribed // 3] = True
    moving_nodes = loading.moving_dofs[0] // 3
    is_moving = np.zeros(len(X), dtype=bool)
    is_moving[moving_nodes] = True
    bounds = {
        "fixed": fem.Boundary(u, mask=clamped & ~is_moving),
        "move": fem.Boundary(u, mask=is_moving, skip=(0, 1, 1)),
        "move-yz": fem.Boundary(u, mask=is_moving, skip=(1, 0, 0)),
    }
    return bounds, moving_nodes, float(loading.u_hat[loading.moving_dofs[0][0]])


def _one(code: str, problem: str) -> None:
    out = run_vlab(problem) if code == "vlab" else run_felupe(problem)
    print("RESULT " + json.dumps(out))


def _child(code: str, problem: str, script: str = __file__) -> dict:
    """Run ``script --one CODE PROBLEM`` in a fresh process; its RESULT line, or its last error."""
    proc = subprocess.run([sys.executable, script, "--one", code, problem], capture_output=True,
                          text=True, cwd=ROOT, env=os.environ | {"VLAB_BENCH_NEWTON": NEWTON})
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[7:])
    return {"error": (proc.stderr.strip().splitlines() or ["no output"])[-1]}


def interleaved_runs(problem: str, repeat: int, script: str = __file__) -> dict[str, list[dict]]:
    """``repeat`` runs of each code on the problem, alternating vlab and FElupe (so a change in the
    machine's load falls on both), each in its own process."""
    runs = {"vlab": [], "felupe": []}
    for _ in range(repeat):
        for code in runs:
            runs[code].append(_child(code, problem, script))
    return runs


def _best(runs: list[dict]) -> dict:
    """The fastest run; for vlab its floor is the lowest measured in any run (the harsher one:
    on a shared machine a floor taken in a slow moment would flatter the ratio)."""
    ok = [r for r in runs if "error" not in r]
    if not ok:
        return runs[-1]
    best = dict(min(ok, key=lambda r: r["total"]))
    if "floor_per_iteration" in best:
        best["floor_per_iteration"] = min(r["floor_per_iteration"] for r in ok)
        best["floor"] = best["floor_per_iteration"] * best["factorizations"]
    return best


def _machine() -> str:
    import psutil

    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg()[0]
    return (f"{cpu}, {os.cpu_count()} cores, {psutil.virtual_memory().total / 2**30:.0f} GiB; "
            f"Python {platform.python_version()}, {platform.system()} {platform.release()}; "
            f"load average {load:.1f} at the start (machine shared with other jobs)")


def _table(rows: list[tuple[str, dict, dict]]) -> str:
    head = ("| problem | DOFs | iterations vlab (exact) / FElupe | factorizations vlab | vlab s | assembly | factorization | assembly/factorization | solve | "
            "other | floor s | vlab/floor | floor/it s | vlab/(floor/it) | FElupe s | vlab/FElupe | peak MB vlab / FElupe | "
            "force rel. diff |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for name, v, f in rows:
        if "error" in v:
            lines.append(f"| {name} | vlab failed: {v['error']} |")
            continue
        fe_ok = "error" not in f
        diff = abs(v["force"] - f["force"]) / abs(f["force"]) if fe_ok else float("nan")
        plain = f["iterations"] if fe_ok else v["iterations"]  # a plain Newton's iterations
        lines.append(
            f"| {name} | {v['dofs']} | {v['iterations']} ({v['exact_iterations']}) / "
            f"{f.get('iterations', '-')} | {v['factorizations']} | {v['total']:.2f} | "
            f"{v['assembly']:.2f} | {v['factorization']:.2f} | {v['assembly'] / v['factorization']:.1%} | "
            f"{v['solve']:.2f} | {v['other']:.2f} | "
            f"{v['floor']:.2f} | {v['total'] / v['floor']:.2f} | "
            f"{v['floor_per_iteration'] * plain:.2f} | "
            f"{v['total'] / (v['floor_per_iteration'] * plain):.2f} | "
            + (f"{f['total']:.2f} | {v['total'] / f['total']:.2f} | {v['peak_mb']:.0f} / {f['peak_mb']:.0f} | "
               f"{diff:.1e} |" if fe_ok else f"failed: {f['error']} | - | {v['peak_mb']:.0f} / - | - |"))
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--one", nargs=2, metavar=("CODE", "PROBLEM"), help=argparse.SUPPRESS)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--problems", default=",".join(PROBLEMS))
    parser.add_argument("--newton", choices=("reuse", "exact"), default="reuse",
                        help="solver.newton of the vlab runs")
    parser.add_argument("--out", type=Path, default=None, help="write the table to this Markdown file")
    args = parser.parse_args()
    if args.one:  # a child: the mode comes from VLAB_BENCH_NEWTON, set by the parent
        _one(*args.one)
        return
    global NEWTON
    NEWTON = args.newton
    machine = _machine()
    rows = []
    for problem in args.problems.split(","):
        runs = interleaved_runs(problem, args.repeat)
        v, f = _best(runs["vlab"]), _best(runs["felupe"])
        rows.append((problem, v, f))
        print(f"{problem}: vlab {v.get('total', float('nan')):.2f} s ({v.get('solver', '?')}), "
              f"FElupe {f.get('total', float('nan')):.2f} s ({f.get('solver', '?')})", flush=True)
    table = _table(rows)
    print(table)
    if args.out:
        command = "python benchmarks/run.py " + " ".join(sys.argv[1:])
        args.out.write_text(
            "# vlab benchmark: vlab vs its cost floor vs FElupe\n\n"
            f"Command: `{command}`\n\nMachine: {machine}\n\n"
            f"Times in seconds, best of {args.repeat} runs, each in its own process.\n\n"
            + __doc__.split("\n\n", 3)[3] + "\n"
            + table + "\n")


if __name__ == "__main__":
    main()
