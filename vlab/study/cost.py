"""What accuracy costs in time: one scene re-run with the knobs that trade accuracy for time.

Knobs (each varied alone around the scene as given, except mesh size which is swept for every
element order and cell type the shape allows):
    mesh size    ``levels`` sizes h0 · ratio^k (k = 1, 0, −1, …; h0 = the scene's mesh.size,
                 gauge_size scaled alike), for order 1 and 2, tet and hex;
    load steps   test.steps ÷ 2, as given, × 2;
    Newton tol.  solver.rtol 1e-4, 1e-6, 1e-8, 1e-10;
    model        the scene's model and ``linear`` (the cheapest: one factorization per test).

Reference (error = |q − q_ref| / |q_ref| for q = E, ν, final force, final stress):
    analytic     uniaxial block with roller grips: the homogeneous solution of the scene's model
                 at the recorded stretches, fitted over the same window (the test kind's reference, vlab.loading.kinds);
    Richardson   otherwise: each mesh family (order, cell) extrapolated on its effective element
                 size h_eff from its three finest levels; the reference of a quantity is the family
                 closest to its own limit (vlab.study.reference), the observed order of every
                 family is stated with the sizes it came from.
The error of a run is the largest of the four relative errors; its time is the run's compute time
(mesh + solve + measure; the report's time is tabulated separately).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from vlab.scene import Scene, apply_overrides
from vlab.study.grid import GridPoint
from vlab.study.pareto import pareto_front
from vlab.study.reference import richardson_reference
from vlab.study.summary import QUANTITIES

RTOLS = (1e-4, 1e-6, 1e-8, 1e-10)
ROUND_OFF_ERROR = 1e-9  # relative errors below this are round-off, not discretization
SOLVER_FLOOR = 10.0  # × solver.rtol: the error a state converged to rtol may carry


@dataclass(frozen=True)
class CostOptions:
    levels: int = 4  # mesh sizes per family (≥ 3 for Richardson; the issue asks for ≥ 4)
    ratio: float = math.sqrt(2.0)  # between successive mesh sizes
    target: float = 0.01  # relative accuracy asked for
    orders: tuple[int, ...] = (1, 2)
    cells: tuple[str, ...] = ("tet", "hex")


GMSH_TET = "gmsh-tet"  # --cells entry: Gmsh's Delaunay tetrahedra (dogbones; the cad extra)


def mesh_family(order: int, cell: str) -> str:
    return f"mesh size (order {order}, {cell})"


def fixed_mesh_note(scene: Scene) -> str | None:
    """Why a study has no mesh-size family, or None: an imported mesh (specimen.shape = "mesh") is
    the file's, and vlab does not refine it (mesh.size does not apply to it)."""
    if scene.specimen.shape != "mesh":
        return None
    return ("mesh size: not studied: specimen.shape = 'mesh' is meshed already and vlab does not refine a "
            "file's mesh (--levels, --orders, --cells do not apply); the errors are the load stepping's, the "
            "Newton tolerance's and the model's against the tightest-tolerance run on the file's mesh. For a "
            "mesh study, mesh the part at each size yourself, or give its geometry as specimen.shape = 'cad'")


def knob_points(scene: Scene, options: CostOptions) -> list[GridPoint]:
    """Every run of the study; labels carry the knob, its value and the family's mesh size (no
    mesh-size family for an imported mesh: fixed_mesh_note)."""
    src, mesh = scene.source, scene.mesh
    points = []

    def add(knob: str, value, overrides: dict):
        label = {"knob": knob, "value": value}
        points.append(GridPoint(label, apply_overrides(src, overrides), scene.base_dir))

    for order in options.orders if fixed_mesh_note(scene) is None else ():
        for cell in options.cells:
            for k in range(options.levels):
                factor = options.ratio ** (1 - k)
                over = {"mesh.size": round(mesh.size * factor, 6), "mesh.order": order, "mesh.cell": cell}
                if cell == GMSH_TET:  # a dogbone's tetrahedra from Gmsh instead of split hexahedra
                    over |= {"mesh.cell": "tet", "mesh.mesher": "gmsh"}
                if mesh.gauge_size is not None:
                    over["mesh.gauge_size"] = round(mesh.gauge_size * factor, 6)
                add(mesh_family(order, cell), over["mesh.size"], over)
    steps = scene.test.steps
    for n in sorted({max(1, steps // 2), steps, 2 * steps}):
        add("load steps", n, {"test.steps": n})
    for rtol in RTOLS:
        add("Newton rtol", rtol, {"solver.rtol": rtol})
    for model in dict.fromkeys(("linear", scene.material.model)):
        add("material model", model, {"material.model": model})
    return points


@dataclass
class CostAnalysis:
    reference_kind: str  # "analytic" | "richardson"
    reference: dict[str, float | None]
    orders: dict[str, float | None]  # observed convergence order per quantity (Richardson)
    notes: dict[str, str]  # per quantity: why no order / round-off
    round_off: bool  # every mesh of the study is at round-off
    errors: list[dict | None]  # per run: relative error per quantity + "max"
    front: list[int] = field(default_factory=list)  # Pareto-optimal runs (indices)
    recommendation: str = ""
    best: int | None = None  # index of the recommended run
    fits: dict[str, list[dict]] = field(default_factory=dict)  # Richardson: per quantity, per family


def run_seconds(summary: dict) -> float:
    """The run's compute time: mesh + solve + measure (the report's time is in the table only:
    it hardly depends on the knobs and would hide the solver's trade-off)."""
    return float((summary.get("timing") or {}).get("total_s") or 0.0)


def analyse(scene: Scene, summaries: list[dict], options: CostOptions) -> CostAnalysis:
    ok = [s.get("status") == "ok" for s in summaries]
    own = [s.get("analytic") for s, good in zip(summaries, ok)
           if good and s.get("model") == scene.material.model]
    if own and all(a is not None and a.get("E") is not None for a in own):
        kind, analysis = "analytic", _analytic(scene, summaries, ok)
    else:
        families = [mesh_family(o, c) for o in options.orders for c in options.cells]
        kind, analysis = "richardson", _richardson(summaries, ok, families)
    analysis.reference_kind = kind
    times = [(run_seconds(s), _floor(e["max"])) if e else None for s, e in zip(summaries, analysis.errors)]
    valid = [i for i, p in enumerate(times) if p is not None and math.isfinite(p[1])]
    analysis.front = [valid[j] for j in pareto_front([times[i] for i in valid])]
    analysis.best, analysis.recommendation = _recommend(summaries, analysis, options.target)
    return analysis


def _floor(x: float | None) -> float:
    return float("nan") if x is None else max(x, 1e-17)


def _relative(q, ref) -> float | None:
    if q is None or ref is None or ref == 0.0:
        return None
    return abs(q - ref) / abs(ref)


def _errors(summary: dict, reference: dict) -> dict | None:
    if summary.get("status") != "ok":
        return None
    errs = {q: _relative(summary["measured"].get(q), reference.get(q)) for q in QUANTITIES}
    known = [e for e in errs.values() if e is not None]
    return errs | {"max": max(known) if known else None}


def _analytic(scene: Scene, summaries: list[dict], ok: list[bool]) -> CostAnalysis:
    """Each run against the analytic solution of the scene's model (runs of another model are
    compared with the analytic values of a run of the scene's model: that is their model error)."""
    own = [s for s, good in zip(summaries, ok) if good and s.get("model") == scene.material.model]
    scene_reference = own[0]["analytic"] if own else {}
    errors = []
    for s, good in zip(summaries, ok):
        ref = s["analytic"] if good and s.get("model") == scene.material.model else scene_reference
        errors.append(_errors(s, ref) if good else None)
    mesh_runs = [e for s, e in zip(summaries, errors) if e and s["label"]["knob"].startswith("mesh size")]
    # E and ν are fitted from small-strain states that Newton solves to rtol, not to round-off
    floor = max(ROUND_OFF_ERROR, SOLVER_FLOOR * scene.solver.rtol)
    round_off = bool(mesh_runs) and all(e["max"] is not None and e["max"] < floor for e in mesh_runs)
    notes = {q: "analytic homogeneous solution" for q in QUANTITIES}
    if round_off:
        notes = {q: f"every mesh is exact up to round-off and the Newton tolerance (errors < {floor:.0e}; "
                    f"the homogeneous state lies in the element space): no convergence trend exists to fit"
                 for q in QUANTITIES}
    return CostAnalysis("analytic", scene_reference, {q: None for q in QUANTITIES}, notes, round_off, errors)


def _richardson(summaries: list[dict], ok: list[bool], families: list[str]) -> CostAnalysis:
    ref = richardson_reference(summaries, ok, families)
    round_off = all(fits and all("round-off" in fit.reason for fit in fits) for fits in ref.fits.values())
    errors = []
    for i, (s, good) in enumerate(zip(summaries, ok)):
        e = _errors(s, ref.values) if good else None
        if e is not None:  # the fallback reference run: its own error is unknown, not zero
            unknown = [q for q in QUANTITIES if ref.fallback_run[q] == i and not round_off]
            if unknown:
                e = e | {q: None for q in unknown}
                known = [e[q] for q in QUANTITIES if e[q] is not None]
                e["max"] = max(known) if known else None
        errors.append(e)
    analysis = CostAnalysis("richardson", ref.values, ref.orders, ref.notes, round_off, errors)
    analysis.fits = {q: [fit.as_dict() for fit in fits] for q, fits in ref.fits.items()}
    return analysis


def describe(summary: dict) -> str:
    label, mesh = summary["label"], summary.get("mesh") or {}
    return (f"{label['knob']} = {label['value']} ({mesh.get('cell')} order {mesh.get('order')}, "
            f"mesh.size {mesh.get('size')}, {mesh.get('dofs')} DOFs, {summary.get('model')}, "
            f"{summary.get('steps')} steps, rtol {(summary.get('solver') or {}).get('rtol')})")


def _recommend(summaries: list[dict], analysis: CostAnalysis, target: float) -> tuple[int | None, str]:
    reached = [i for i, e in enumerate(analysis.errors)
               if e and e["max"] is not None and e["max"] <= target]
    if analysis.round_off:
        lead = ("Every mesh reproduces the reference to round-off, so refinement buys nothing here: "
                "the coarsest, lowest-order mesh is as accurate as any. ")
    else:
        lead = ""
    if not reached:
        scored = [i for i, e in enumerate(analysis.errors) if e and e["max"] is not None]
        if not scored:
            return None, lead + "No run completed, so nothing can be recommended."
        best = min(scored, key=lambda i: analysis.errors[i]["max"])
        return None, (lead + f"No setting reached the requested {target:.3g} relative error; the most "
                      f"accurate was {describe(summaries[best])} with {analysis.errors[best]['max']:.3g} "
                      f"in {run_seconds(summaries[best]):.3g} s. Refine further or raise the order.")
    best = min(reached, key=lambda i: run_seconds(summaries[i]))
    e = analysis.errors[best]
    return best, (lead + f"Cheapest setting reaching {target:.3g}: {describe(summaries[best])}, "
                  f"{run_seconds(summaries[best]):.3g} s, largest relative error {e['max']:.2g} "
                  f"(E {_pct(e['E'])}, ν {_pct(e['nu'])}, final stress {_pct(e['final_stress'])}).")


def _pct(x) -> str:
    return "—" if x is None else f"{x:.2g}"


def time_to_target(summaries: list[dict], analysis: CostAnalysis, knob: str, target: float) -> float | None:
    """Shortest run time of ``knob``'s runs whose error is ≤ target (None if none reaches it)."""
    times = [run_seconds(s) for s, e in zip(summaries, analysis.errors)
             if e and s["label"]["knob"] == knob and e["max"] is not None and e["max"] <= target]
    return min(times) if times else None
