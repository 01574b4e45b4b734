"""RunResult -> the plain dict written as results.json (and read back by reports and tests)."""

from __future__ import annotations

import datetime as _dt
import math

from typing import TYPE_CHECKING

import numpy as np

from vlab import __version__

if TYPE_CHECKING:
    from vlab.fe.stepping import Failure
    from vlab.run import RunResult
    from vlab.scene import Scene


def stretch_at(scene: Scene, t: float) -> list[float]:
    """The control values at load parameter t (grip stretches; simple shear: γ)."""
    from vlab.loading.kinds import kind_of

    return kind_of(scene.test).at(scene.test.targets, t)


def failure_dict(scene: Scene, failure: Failure) -> dict:
    return {
        "step": failure.level,
        "stretch": stretch_at(scene, failure.t_attempted),
        "target_stretch": stretch_at(scene, failure.t_target),
        "last_converged_stretch": stretch_at(scene, failure.t_converged),
        "reason": failure.reason,
        "residual_history": failure.residuals,
        "min_J": failure.min_J,
        "element": failure.element,
        "quadrature_point": failure.quadrature_point,
    }


def observed_order(residuals: list[float], floor: float = 1e-10) -> float | None:
    """Convergence order p from the last three relative residuals above ``floor``: r₊ ≈ C r^p.

    Relative residuals below ~1e-10 are dominated by round-off in the force sums, so they say
    nothing about the order; None when fewer than three iterates lie above the floor."""
    r = [x for x in residuals if x > floor]
    if len(r) < 3 or r[-2] == r[-3]:
        return None
    return float(np.log(r[-1] / r[-2]) / np.log(r[-2] / r[-3]))


def _clean(value):
    """JSON-safe: numpy scalars to float, NaN/inf to None (results never carry NaN)."""
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def curve_columns(result: RunResult) -> dict[str, list[float]]:
    """Named curve columns: the test kind's (vlab.loading.kinds: ``columns``; stretch kinds: axis 0
    unsuffixed, axis 1 suffixed ``_y``), then time, centre averages and the lateral gauges."""
    c = result.curve
    cols = _kind(result).columns(c)  # the test's variant (a phased tension–torsion adds its phase)
    if c.time:
        cols["time"] = list(c.time)
    for key, values in c.centre.items():  # cruciform: FE centre averages, e.g. centre_stress_x
        cols[f"centre_{key}"] = list(values)
    cols["transverse_strain"] = list(c.transverse_strain)
    cols["thickness_strain"] = list(c.thickness_strain)
    return cols


def result_to_dict(result: RunResult) -> dict:
    """The results.json dict of a run (JSON-safe: NaN/inf as None)."""
    scene, history, d = result.scene, result.history, result.diagnostics
    return _clean(_with_dic(result, {
        "vlab_version": __version__,
        "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "scene": {"name": scene.name, "hash": scene.content_hash(), "source": scene.source},
        "converged": result.converged,
        "measured": _measured(result),
        "input": material_input(scene.material),
        "curve": (columns := curve_columns(result)) | {"units": _kind(result).units_of(columns)},
        "specimen": _instrument_geometry(result),
        "reference": result.reference,
        "homogeneity": d.homogeneity,
        "bending": d.bending,  # test.misalignment: ASTM E1012 percent bending (measure/bending.py)
        "cruciform": d.cruciform,
        "solver": _solver(result),
        "timing": result.timing,
        "mesh": _mesh(result),
        "stability": d.stability,
        "effects": d.effects,
        "critical": d.critical,  # first loss of stability (buckling or not)
        "lateral_deflection": d.lateral_deflection,  # mm, per level
        "imperfection": (None if d.imperfection is None else
                         {"amplitude_over_thickness": scene.test.imperfection, **d.imperfection}),
        "warnings": d.warnings,
        "failure": None if history.failure is None else failure_dict(scene, history.failure),
        "accuracy_estimate": d.accuracy_estimate,  # vlab.study.estimate; None if off
    }))


def _with_dic(result: RunResult, data: dict) -> dict:
    """measured.dic and dic (vlab.report.dic_report) for a scene with [instruments.dic]."""
    if getattr(result, "dic", None) is None:
        return data
    from vlab.report.dic_report import measured_dict, summary_dict

    data["measured"]["dic"] = measured_dict(result)
    data["dic"] = summary_dict(result)
    return data


def _instrument_geometry(result: RunResult) -> dict:
    """The full specimen's initial grip separation L₀ (mm) per loaded axis (x, y), so a reader turns
    the crosshead strain back into the machine's crosshead displacement Δ = (λ − 1) L₀ (mm)."""
    sep = getattr(result.specimen, "grip_separation", None) or {}
    return {"grip_separation": {"xy"[a]: float(sep[a]) for a in _kind(result).axes if a in sep},
            "units": {"grip_separation": "mm"}}


def _measured(result: RunResult) -> dict:
    const, d = result.constants, result.diagnostics
    return {
        "E": const.E, "nu": const.nu, "E_fit": const.E_fit, "nu_fit": const.nu_fit,
        "axes": const.per_axis, "note": const.note,
        "E_crosshead": (d.crosshead or {}).get("E"),
        "E_crosshead_fit": (d.crosshead or {}).get("fit"),
        "window": list(result.scene.measure.modulus_window),  # |extensometer strain| of the E, nu fits
        "uncertainty": d.uncertainty,  # effects.noise: intervals, noiseless E, nu
        "units": {"E": "MPa", "nu": "1"} | _kind(result).measured_units,
    } | const.extra


def _kind(result: RunResult):
    from vlab.loading.kinds import kind_of

    return kind_of(result.scene.test)


def _solver(result: RunResult) -> dict:
    levels, solver = result.history.levels, result.scene.solver
    return {
        "newton_iterations": [lv.iterations for lv in levels],
        "cutbacks": [lv.cutbacks for lv in levels],
        "repairs": [sum(r.repairs for r in lv.newton) for lv in levels],
        "residual_history": [[x for rec in lv.newton for x in rec.residuals] for lv in levels],
        "observed_order": [observed_order(r.residuals) for lv in levels for r in lv.newton[-1:]],
        "newton": solver.newton,
        "exact_iterations": [sum(r.exact for r in lv.newton) for lv in levels],
        "factorizations": result.history.factorizations,
        "linear": result.diagnostics.linear_solver,
        "tangent_kernel": result.diagnostics.tangent_kernel,
        "rtol": solver.rtol,
    }


def _mesh(result: RunResult) -> dict:
    mesh, space = result.scene.mesh, result.space
    return {
        "cell": mesh.cell, "order": mesh.order, "size": mesh.size,
        "formulation": mesh.formulation,
        "symmetry": mesh.symmetry,
        "elements": int(space.basis.nelems), "nodes": int(space.n_nodes), "dofs": int(space.n_dofs),
        "quality": result.diagnostics.mesh_quality,
    }


def material_input(material) -> dict:
    """results.json → input: the model, its card (constants, volumetric form) and the small-strain
    constants every model implies (μ0, K, E, ν; a Lamé-pair model's μ0 is its μ)."""
    m = material.moduli
    out = {"model": material.model, **m.as_dict(),
           "small_strain": {"mu0": m.mu, "K": m.K, "E": m.E, "nu": m.nu,
                            "units": {"mu0": "MPa", "K": "MPa", "E": "MPa", "nu": "1"}}}
    if material.params:
        out["parameters"] = {k: list(v) if isinstance(v, tuple) else v for k, v in material.params.items()}
        out["bulk_as_given"] = dict(material.given)
        out["volumetric"] = material.volumetric
    return out

