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
    return [1.0 + t * (s - 1.0) for s in scene.test.stretch]


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
    """Named curve columns; axis 0 unsuffixed, axis 1 (biaxial) suffixed ``_y``."""
    c = result.curve
    cols: dict[str, list[float]] = {}
    for axis in c.axes:
        sfx = "" if axis == 0 else "_y"
        cols["stretch" + sfx] = list(c.stretch[axis])
        cols["strain" + sfx] = list(c.strain[axis])
        cols["stress" + sfx] = list(c.column("stress", axis))
        cols["force" + sfx] = list(c.force[axis])
        cols["true_strain" + sfx] = list(c.column("true_strain", axis))
        cols["true_stress" + sfx] = list(c.column("true_stress", axis))
    if len(c.axes) == 1:
        cols["crosshead_strain"] = [s - 1.0 for s in c.stretch[0]]
    if c.time:
        cols["time"] = list(c.time)
    for key, values in c.centre.items():  # cruciform: FE centre averages, e.g. centre_stress_x
        cols[f"centre_{key}"] = list(values)
    cols["transverse_strain"] = list(c.transverse_strain)
    cols["thickness_strain"] = list(c.thickness_strain)
    return cols


def result_to_dict(result: RunResult) -> dict:
    scene, history, const = result.scene, result.history, result.constants
    levels = history.levels
    residuals = [[x for rec in lv.newton for x in rec.residuals] for lv in levels]
    space = result.space
    return _clean({
        "vlab_version": __version__,
        "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "scene": {"name": scene.name, "hash": scene.content_hash(), "source": scene.source},
        "converged": result.converged,
        "measured": {
            "E": const.E, "nu": const.nu, "E_fit": const.E_fit, "nu_fit": const.nu_fit,
            "axes": const.per_axis, "note": const.note,
            "E_crosshead": (result.extra.get("crosshead") or {}).get("E"),
            "E_crosshead_fit": (result.extra.get("crosshead") or {}).get("fit"),
            "window": list(scene.measure.modulus_window),  # |extensometer strain| of the E, nu fits
            "uncertainty": result.extra.get("uncertainty"),  # effects.noise: intervals, noiseless E, nu
            "units": {"E": "MPa", "nu": "1"},
        },
        "input": {"model": scene.material.model, **scene.material.moduli.as_dict()},
        "curve": curve_columns(result) | {
            "units": {"stretch": "1 (grip)", "strain": "1 (extensometer, engineering)",
                      "stress": "MPa (engineering)", "force": "N", "true_stress": "MPa",
                      "crosshead_strain": "1 (grip separation change / initial grip separation)",
                      "time": "s"},
        },
        "reference": result.reference,
        "homogeneity": result.extra.get("homogeneity"),
        "cruciform": result.extra.get("cruciform"),
        "solver": {
            "newton_iterations": [lv.iterations for lv in levels],
            "cutbacks": [lv.cutbacks for lv in levels],
            "repairs": [sum(r.repairs for r in lv.newton) for lv in levels],
            "residual_history": residuals,
            "observed_order": [observed_order(r.residuals) for lv in levels for r in lv.newton[-1:]],
            "newton": scene.solver.newton,
            "exact_iterations": [sum(r.exact for r in lv.newton) for lv in levels],
            "factorizations": history.factorizations,
            "linear": result.extra.get("linear_solver"),
            "tangent_kernel": result.extra.get("tangent_kernel"),
            "rtol": scene.solver.rtol,
        },
        "timing": result.timing,
        "mesh": {
            "cell": scene.mesh.cell, "order": scene.mesh.order, "size": scene.mesh.size,
            "formulation": scene.mesh.formulation,
            "symmetry": scene.mesh.symmetry,
            "elements": int(space.basis.nelems), "nodes": int(space.n_nodes), "dofs": int(space.n_dofs),
            "quality": result.extra.get("mesh_quality"),
        },
        "stability": result.extra.get("stability", []),
        "effects": result.extra.get("effects"),
        "critical": result.extra.get("critical"),  # first loss of stability (buckling or not)
        "lateral_deflection": result.extra.get("lateral_deflection", []),  # mm, per level
        "imperfection": (None if "imperfection" not in result.extra else
                         {"amplitude_over_thickness": scene.test.imperfection,
                          "perfect_critical": result.extra["imperfection"]["perfect_critical"]}),
        "warnings": result.extra.get("warnings", []),
        "failure": None if history.failure is None else failure_dict(scene, history.failure),
        "accuracy_estimate": result.extra.get("accuracy_estimate"),  # vlab.study.estimate; None if off
    })
