"""The built-in cases of ``vlab stability`` (issue 5): each converges to the right answer or stops
with a diagnosis a user can act on. Numbers in the expectations are the oracles (analytic values,
Euler's formula) and the tolerances the suite holds them to."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import skfem

from vlab.fe.assembly import Partition
from vlab.fe.newton import NewtonOptions
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.fe.system import System
from vlab.fe.stepping import Stepping, run_schedule
from vlab.geometry.block import block_mesh
from vlab.geometry.perturb import perturbed
from vlab.geometry.mesh_check import MeshError, check_mesh
from vlab.loading.grips import grip_loading
from vlab.materials import make_material
from vlab.report.results import result_to_dict
from vlab.run import MeshQualityError, build_specimen, run_scene
from vlab.scene import parse_scene
from vlab.loading.restraint import unrestrained_modes
from vlab.verification.euler import clamped_strip
from vlab.verification.suite import CaseContext, Outcome, register

INV_SQRT3 = 1.0 / math.sqrt(3.0)


def block(model: str, stretch, *, grips: str = "roller", size: float = 10.0, steps: int = 10,
          extent=(10.0, 10.0, 10.0), cell: str = "hex", nu: float = 0.3):
    return parse_scene({"name": "case", "specimen": {"shape": "block", "size": list(extent)},
                        "mesh": {"size": size, "cell": cell},
                        "material": {"model": model, "E": 10.0, "nu": nu},
                        "test": {"kind": "uniaxial", "grips": grips, "stretch": stretch, "steps": steps}})


def from_run(data: dict, got: str, passed: bool, **details) -> Outcome:
    """An Outcome carrying a run's cost and stability figures (results.json dict)."""
    negatives = [s["negative_eigenvalues"] for s in data["stability"] if s["negative_eigenvalues"] is not None]
    failure = data["failure"]
    # the stopping level's cutbacks are in no completed level: count its rejected states (or 1)
    rejected = 0 if failure is None else max(1, sum(not s["accepted"] for s in data["stability"]))
    return Outcome(got=got, passed=bool(passed), converged=bool(data["converged"]),
                   iterations=int(sum(data["solver"]["newton_iterations"])),
                   cutbacks=int(sum(data["solver"]["cutbacks"])) + rejected,
                   negative_eigenvalues=max(negatives) if negatives else None,
                   details={"failure": failure and failure["reason"], **details})


def _run(scene, **kwargs) -> dict:
    return result_to_dict(run_scene(scene, **kwargs))


# --- admissibility: StVK's limit point and no-state requests ------------------------------------

@register("stvk-compression-limit-point",
          "stops: load limit point bracketed around 1/√3 = 0.5774 (one hex, roller grips), width < 0.005")
def stvk_limit_point(context: CaseContext) -> Outcome:
    data = _run(block("stvk", 0.3, steps=70))
    f = data["failure"] or {}
    ok_s, bad_s = (f.get("last_converged_stretch") or [None])[0], (f.get("stretch") or [None])[0]
    passed = (not data["converged"] and "load limit point" in f.get("reason", "")
              and bad_s <= INV_SQRT3 <= ok_s and ok_s - bad_s < 0.005)
    return from_run(data, f"stopped: limit point in [{bad_s:.4f}, {ok_s:.4f}]" if f else "converged",
                    passed, bracket=[bad_s, ok_s], oracle=INV_SQRT3)


@register("stvk-tension-refused",
          "refused before solving: no admissible state beyond √(1 + 1/ν) = 2.0817 (ν = 0.3, stretch 2.2)")
def stvk_tension_refused(context: CaseContext) -> Outcome:
    data = _run(block("stvk", 2.2, steps=4))
    reason = (data["failure"] or {}).get("reason", "")
    limit = math.sqrt(1 + 1 / 0.3)
    passed = not data["converged"] and "refused before solving" in reason and f"{limit:.6g}" in reason
    return from_run(data, "refused: " + reason.split(":", 1)[-1].strip()[:100] if reason else "converged",
                    passed, limit=limit)


def _carries_on(model: str, stretch: float, steps: int) -> Outcome:
    data = _run(block(model, stretch, steps=steps))
    stable = all(s["negative_eigenvalues"] == 0 and s["accepted"] for s in data["stability"])
    reached = data["curve"]["stretch"][-1] if data["curve"]["stretch"] else None
    passed = data["converged"] and stable and math.isclose(reached, stretch)
    return from_run(data, f"converged to {reached:g}, all states stable" if passed else
                    f"stopped at {reached}: {(data['failure'] or {}).get('reason', '')[:60]}", passed)


for _model in ("stvk-volumetric", "neo-hookean"):
    for _stretch, _steps, _what in ((0.3, 70, "compression"), (2.2, 4, "tension")):
        register(f"{_model}-{_what}-{_stretch}",
                 f"converges to stretch {_stretch} with K_ff positive definite throughout "
                 f"(where StVK {'collapses' if _stretch < 1 else 'has no state'})")(
            lambda context, m=_model, s=_stretch, n=_steps: _carries_on(m, s, n))


# --- inversion, missing grip ----------------------------------------------------------------------

@register("inversion-stop",
          "stops after cutbacks with the element, quadrature point and min J ≤ 0 (grip pushed through)")
def inversion_stop(context: CaseContext) -> Outcome:
    scene = block("neo-hookean", 0.5, grips="clamped", size=5.0)
    spec = build_specimen(scene)
    space = DisplacementSpace.build(spec.mesh, 1)
    body = HyperelasticBody(space, make_material("neo-hookean", 5.77, 3.85))
    loading = grip_loading(spec, space.node_coordinates, (-0.2,), "clamped")  # grips cross at t = 1/1.2
    partition = Partition.build(body.pattern, loading.prescribed)
    history = run_schedule(System(body, partition, loading.u_hat, (1e-12, 17.3)),
                           Stepping(np.array([1.0]), max_cutbacks=6, newton=NewtonOptions(max_iterations=15)))
    f = history.failure
    passed = (f is not None and f.min_J is not None and f.min_J <= 0.0 and f.element is not None
              and f.quadrature_point is not None and f.t_converged < 1 / 1.2)
    got = (f"stopped at t = {f.t_attempted:.3f}: element {f.element}, point {f.quadrature_point}, "
           f"min J = {f.min_J:.3g}" if f else "converged")
    return Outcome(got, passed, converged=f is None,
                   iterations=sum(lv.iterations for lv in history.levels), cutbacks=6,
                   details={"failure": f and f.reason, "min_J": f and f.min_J})


@register("missing-grip-under-constrained",
          "refused: the rigid-body modes left free are named; if solved anyway, the unloaded K_ff "
          "is found singular (zero pivots or eigenvalues) before any load step")
def missing_grip(context: CaseContext) -> Outcome:
    """Roller grips without the 3-2-1 supports. The exact restraint check names the free modes
    before any solve (run_scene refuses there). Solved anyway, a sparse Cholesky may return a
    finite "solution" (the load is orthogonal to the free modes); the stability monitor's inertia
    counts the zero pivots and rejects the state; the stepper checks the unloaded K_ff first."""
    from vlab.checks.monitor import StabilityMonitor
    from vlab.loading.kinds import KINDS

    scene = block("neo-hookean", 1.2, size=5.0)
    spec = build_specimen(scene)
    space = DisplacementSpace.build(spec.mesh, 1)
    body = HyperelasticBody(space, make_material("neo-hookean", 5.77, 3.85))
    loading = grip_loading(spec, space.node_coordinates, (1.2,), "roller")
    grip_dofs = loading.prescribed[loading.prescribed % 3 == 0]  # the grips alone, no 3-2-1 supports
    modes = unrestrained_modes(space.node_coordinates, grip_dofs)
    partition = Partition.build(body.pattern, grip_dofs)
    monitor = StabilityMonitor(body, partition, loading.moving_dofs, KINDS["uniaxial"], (1.2,), "neo-hookean",
                               loading.u_hat)
    history = run_schedule(System(body, partition, loading.u_hat, (1e-12, 17.3)),
                           Stepping(np.array([1.0]), max_cutbacks=2, accept=monitor.accept))
    zeros = max((r.zero_eigenvalues or 0 for r in monitor.records), default=0)
    reason = history.failure.reason if history.failure is not None else ""
    caught = zeros == 3 or "singular" in reason  # by the monitor's inertia, or before any step
    passed = len(modes) == 3 and history.failure is not None and caught
    return Outcome(f"{len(modes)} free modes named ({'; '.join(modes)}); solved anyway: "
                   f"{reason or f'{zeros} zero eigenvalues'}",
                   passed, converged=history.failure is None, cutbacks=2,
                   negative_eigenvalues=max((r.negative_eigenvalues or 0 for r in monitor.records), default=None),
                   details={"modes": modes, "failure": history.failure and history.failure.reason})


# --- meshes --------------------------------------------------------------------------------------

@register("perturbed-mesh-patch-test",
          "20 % randomly distorted hex mesh, roller grips to 1.6: stress within 1e-6 of the analytic curve")
def perturbed_patch(context: CaseContext) -> Outcome:
    scene = block("neo-hookean", 1.6, size=2.5, steps=4)
    data = _run(scene, specimen=perturbed(build_specimen(scene), 0.2, seed=1))
    error = data["reference"]["max_relative_error_x"]
    q = data["mesh"]["quality"]
    return from_run(data, f"max relative error {error:.2g} (worst quality {q['min_quality']:.2f})",
                    data["converged"] and error < 1e-6, error=error)


@register("perturbed-mesh-clamped",
          "20 % distorted tet mesh, clamped grips to 1.3: grip force within 0.5 % of the regular mesh")
def perturbed_clamped(context: CaseContext) -> Outcome:
    scene = block("neo-hookean", 1.3, grips="clamped", size=2.5, steps=3, cell="tet")
    regular = _run(scene)
    moved = _run(scene, specimen=perturbed(build_specimen(scene), 0.2, seed=2))
    f0, f1 = regular["curve"]["force"][-1], moved["curve"]["force"][-1]
    diff = abs(f1 - f0) / abs(f0)
    return from_run(moved, f"force differs by {100 * diff:.3g} %", moved["converged"] and diff < 0.005,
                    relative_difference=diff)


@register("high-aspect-ratio-cells",
          "10:10:1 hex cells (40 × 10 × 1 mm block), roller grips to 1.6: within 1e-6 of the analytic curve")
def high_aspect(context: CaseContext) -> Outcome:
    data = _run(block("neo-hookean", 1.6, size=10.0, steps=4, extent=(40.0, 10.0, 1.0)))
    error = data["reference"]["max_relative_error_x"]
    return from_run(data, f"max relative error {error:.2g}", data["converged"] and error < 1e-6, error=error)


@register("invalid-meshes-refused",
          "inverted element, duplicate and unused nodes, a sliver: each a clear error before solving")
def invalid_meshes(context: CaseContext) -> Outcome:
    messages = []
    scene = block("neo-hookean", 1.2, size=5.0)
    spec = build_specimen(scene)
    p = spec.mesh.p.copy()
    inner = np.flatnonzero(np.all((p > 1e-9) & (p < 10 - 1e-9), axis=0))
    p[:, inner[0]] = [12.0, 5.0, 5.0]
    try:
        run_scene(scene, specimen=dataclasses.replace(spec, mesh=type(spec.mesh)(p, spec.mesh.t)))
    except MeshQualityError as exc:
        messages.append(str(exc))
    mesh = block_mesh((2.0, 2.0, 2.0), 1.0, "hex")
    sliver = skfem.MeshTet(np.array([[0.0, 1.0, 0.0, 0.5], [0.0, 0.0, 1.0, 0.5], [0.0, 0.0, 0.0, 0.01]]),
                           np.array([[0], [1], [2], [3]]))
    for bad in (skfem.MeshHex(np.hstack([mesh.p, [[5.0], [5.0], [5.0]]]), mesh.t), sliver):
        try:
            check_mesh(bad)
        except MeshError as exc:
            messages.append(str(exc))
    passed = len(messages) == 3
    return Outcome(f"{len(messages)}/3 refused", passed, converged=False,
                   details={"messages": messages})


# --- buckling of clamped strips ------------------------------------------------------------------

STRIP = {"thickness": 1.0, "width": 2.0, "E": 10.0, "nu": 0.3}
# FE above the small-strain formula: the pre-buckling shortening and thickening, the clamps'
# restraint of the end sections' Poisson expansion; both vanish as the strip gets slender.
STRIP_TOLERANCE = {10: 0.12, 20: 0.04, 40: 0.02}


def strip_scene(slenderness: float, stretch: float | None = None, steps: int = 4, **test):
    euler = clamped_strip(slenderness * STRIP["thickness"], STRIP["width"], STRIP["thickness"],
                          STRIP["E"], STRIP["nu"])
    stretch = stretch if stretch is not None else 1.0 - 2.0 * euler.critical_strain
    return parse_scene({
        "name": f"strip-{slenderness:g}",
        "specimen": {"shape": "block", "size": [slenderness * STRIP["thickness"], STRIP["width"], STRIP["thickness"]]},
        "mesh": {"size": STRIP["thickness"] / 2, "cell": "hex", "order": 2},
        "material": {"model": "neo-hookean", "E": STRIP["E"], "nu": STRIP["nu"]},
        "test": {"kind": "uniaxial", "grips": "clamped", "stretch": stretch, "steps": steps} | test,
        "measure": {"modulus_points": 0}, "solver": {"max_cutbacks": 12}}), euler


def _strip_case(slenderness: int, context: CaseContext) -> Outcome:
    scene, euler = strip_scene(slenderness)
    result = run_scene(scene)
    data = result_to_dict(result)
    c = data["critical"]
    if c is None or c["kind"] != "buckling":
        return from_run(data, "no buckling found", False)
    fe = c["critical_strain"]
    diff = fe / euler.critical_strain - 1.0
    figures = []
    if context.out is not None and context.render:
        figures.append(_render_mode(result, context, f"strip-L{slenderness}-mode.png",
                                    f"buckling mode, clamped strip L/t = {slenderness}\n"
                                    f"critical grip strain {c['strain_bracket'][0]:.4g} .. {c['strain_bracket'][1]:.4g}"))
    out = from_run(data, f"ε_cr = {fe:.5f} vs Euler–shear {euler.critical_strain:.5f} ({100 * diff:+.2f} %)",
                   abs(diff) < STRIP_TOLERANCE[slenderness],
                   slenderness=slenderness, fe_strain=fe, strain_bracket=c["strain_bracket"],
                   euler=euler.as_dict(), relative_difference=diff,
                   relative_difference_current_geometry=fe / euler.current_geometry_strain - 1.0,
                   lateral_fraction=c["lateral_fraction"], dofs=data["mesh"]["dofs"])
    return dataclasses.replace(out, figures=[f for f in figures if f])


def _render_mode(result, context: CaseContext, name: str, label: str) -> str | None:
    from vlab.render.mode import render_mode
    from vlab.render.offscreen import RenderUnavailable

    try:
        render_mode(result.specimen.mesh, result.final_displacement, result.solver.critical_state.mode,
                    context.out / name, label)
    except RenderUnavailable:
        return None
    return name


for _r in (10, 20, 40):
    register(f"buckling-clamped-strip-L{_r}",
             f"loss of positive definiteness reported as buckling; ε_cr within {100 * STRIP_TOLERANCE[_r]:.0f} % of "
             f"P_cr/(EA), P_cr = P_E/(1 + P_E/κGA) (L/t = {_r}, Q2 hexes)", fast=_r == 10)(
        lambda context, r=_r: _strip_case(r, context))


@register("buckling-strip-imperfection",
          "imperfection 0.05 t in the mode: converges past buckling, force stays below the perfect P_cr, "
          "deflection grows monotonically", fast=False)
def strip_imperfection(context: CaseContext) -> Outcome:
    scene, euler = strip_scene(10, stretch=0.9, steps=10, imperfection=0.05)
    data = _run(scene)
    perfect = (data.get("imperfection") or {}).get("perfect_critical") or {}
    force, w = np.abs(data["curve"]["force"]), np.array(data["lateral_deflection"])
    p_cr = abs(perfect.get("force_stable", [np.nan])[0])
    passed = data["converged"] and force.max() < p_cr and bool(np.all(np.diff(w) > 0))
    return from_run(data, f"max force {force.max():.4g} N < P_cr {p_cr:.4g} N; deflection {w[0]:.3g} → {w[-1]:.3g} mm",
                    passed, force=list(force), deflection=list(w), perfect_critical_force=p_cr)


# --- Neo-Hookean dogbone at large stretch and in compression -------------------------------------

def dogbone(stretch: float, steps: int, cell: str = "tet", order: int = 2, size: float = 2.0):
    """ISO 37 type 2 dumb-bell (rubber, E = 3 MPa, ν = 0.45), clamped over its tabs."""
    return parse_scene({"name": "dogbone", "specimen": {"shape": "dogbone", "standard": "ISO 37 2"},
                        "mesh": {"size": size, "cell": cell, "order": order},
                        "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.45},
                        "test": {"kind": "uniaxial", "stretch": stretch, "steps": steps}})


@register("dogbone-neo-hookean-stretch-4",
          "P2 tets: converges to grip stretch 4 with K_ff positive definite at every level", fast=False)
def dogbone_stretch(context: CaseContext) -> Outcome:
    result = run_scene(dogbone(4.0, 20))
    data = result_to_dict(result)
    stable = all(s["negative_eigenvalues"] == 0 for s in data["stability"])
    reached = data["curve"]["stretch"][-1]
    min_J = min(level.state.min_J for level in result.history.levels)
    return from_run(data, f"converged to {reached:g}, min J {min_J:.3g}, force {data['curve']['force'][-1]:.3g} N"
                    if data["converged"] else f"stopped at {reached:g}: {data['failure']['reason'][:80]}",
                    data["converged"] and stable and reached == 4.0, min_J=min_J, dofs=data["mesh"]["dofs"])


@register("dogbone-coarse-hex-stretch-4",
          "one Q1 hex through the thickness: converges or stops with a diagnosed bifurcation (never garbage); "
          "Neo-Hookean stays strongly elliptic, so a stop here is the mesh's, not the material's",
          fast=False)
def dogbone_coarse(context: CaseContext) -> Outcome:
    data = _run(dogbone(4.0, 20, cell="hex", order=1, size=2.5))
    c = data["critical"]
    diagnosed = data["converged"] or (c is not None and "loss of stability" in data["failure"]["reason"])
    got = ("converged to 4" if data["converged"] else
           f"{c['kind']} between stretch {c['stretch_stable'][0]:.4g} and {c['stretch_unstable'][0]:.4g}")
    return from_run(data, got, diagnosed, critical=c)


@register("dogbone-refined-hex-stretch-4",
          "the same Q1 hexes refined to 1 mm over the gauge section converge to stretch 4, all states stable",
          fast=False)
def dogbone_refined(context: CaseContext) -> Outcome:
    scene = parse_scene(dict(dogbone(4.0, 20, cell="hex", order=1, size=2.5).source,
                             mesh={"size": 2.5, "gauge_size": 1.0, "cell": "hex", "order": 1}))
    data = _run(scene)
    stable = all(s["negative_eigenvalues"] == 0 for s in data["stability"])
    return from_run(data, f"converged to {data['curve']['stretch'][-1]:g}" if data["converged"]
                    else f"stopped: {data['failure']['reason'][:80]}", data["converged"] and stable,
                    dofs=data["mesh"]["dofs"])


@register("dogbone-neo-hookean-compression-0.3",
          "clamped dumb-bell in compression buckles long before 0.3: stops, reported as buckling "
          "(a global sideways mode between the grips)", fast=False)
def dogbone_compression(context: CaseContext) -> Outcome:
    result = run_scene(dogbone(0.3, 20))
    data = result_to_dict(result)
    c = data["critical"]
    if c is None:
        return from_run(data, "converged without buckling" if data["converged"] else data["failure"]["reason"][:80], False)
    lo, hi = c["strain_bracket"]
    figures = []
    if context.out is not None and context.render:
        figures.append(_render_mode(result, context, "dogbone-compression-mode.png",
                                    f"dumb-bell ISO 37-2 in compression: {c['kind']}\n"
                                    f"critical grip strain {lo:.4g} .. {hi:.4g}"))
    out = from_run(data, f"{c['kind']} at grip strain {lo:.4g}..{hi:.4g}", c["kind"] == "buckling"
                   and not data["converged"], critical=c)
    return dataclasses.replace(out, figures=[f for f in figures if f])


@register("dogbone-compression-0.3-imperfection",
          "with an imperfection of 0.05 t in its buckling mode the dumb-bell follows the post-buckled path "
          "to 0.3: converged, K_ff positive definite, deflection growing (self-contact is not modelled)",
          fast=False)
def dogbone_post_buckling(context: CaseContext) -> Outcome:
    scene = parse_scene(dict(dogbone(0.3, 20).source,
                             test={"kind": "uniaxial", "stretch": 0.3, "steps": 20, "imperfection": 0.05}))
    data = _run(scene)
    w = np.array(data["lateral_deflection"])
    perfect = (data.get("imperfection") or {}).get("perfect_critical") or {}
    p_cr = abs((perfect.get("force_stable") or [np.nan])[0])
    stable = all(s["negative_eigenvalues"] == 0 for s in data["stability"])
    passed = data["converged"] and stable and bool(np.all(np.diff(w) > 0))
    force = np.abs(data["curve"]["force"])
    return from_run(data, f"converged to {data['curve']['stretch'][-1]:g}: deflection {w[-1]:.3g} mm, force "
                    f"{force[-1]:.3g} N (perfect P_cr {p_cr:.3g} N)" if data["converged"]
                    else f"stopped: {data['failure']['reason'][:80]}", passed,
                    deflection=list(w), force=list(force), perfect_critical_force=p_cr)
