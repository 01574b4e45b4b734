"""What an inflation test measures (vlab.loading.kinds.inflation), and its closed form.

The closed form p(λ_a) lives with the loading, in vlab.loading.thick_sphere.

Readings per level (the inner nodes i of the octant, X_i their reference positions, f_i their
reactions, N):
- the pressure p = Σ f_i · X_i / (3 λ_a² V₀): the wall is driven as x_i = λ_a X_i, so Σ f_i · X_i is
  the generalized force conjugate to λ_a, and the virtual work of a uniform pressure on the
  facetted cavity, V = λ_a³ V₀ (V₀ the octant's cavity volume), is p dV/dλ_a = 3 λ_a² V₀ p;
- λ_a from the wall's own displacement (|x_i| / |X_i|, the same for every inner node);
- ``wall_ratio`` (A/B)³, the constant the closed form needs.
Measures: the limit point (the largest pressure of a rise followed by a fall: the parabola
through the recorded maximum and its two neighbours, its vertex's stretch and pressure), or
None with the reason; and the initial slope dp/dλ_a over the modulus window (λ_a − 1 in it).
"""

from __future__ import annotations

import numpy as np

from vlab.loading.thick_sphere import thick_sphere_pressure
from vlab.measure.elastic_constants import ElasticConstants
from vlab.measure.fit import FitError, fit_line

__all__ = ["cavity_pressure_readers", "inflation_constants", "thick_sphere_pressure", "limit_point"]


def cavity_pressure_readers(space, specimen, loading, material) -> dict:
    """Readers of p (MPa) and of (A/B)³ (module docstring); on a membrane (the liquid-loaded bulge
    test) those of vlab.measure.bulge."""
    if loading.liquid is not None and specimen.shape == "membrane":
        from vlab.measure.bulge import bulge_readers

        return bulge_readers(space, specimen, loading, material)
    nodes = loading.moving_dofs[0] // 3
    X = space.node_coordinates[nodes]
    V0 = specimen.area0[0]
    R = np.linalg.norm(X, axis=1)
    ratio = (specimen.grip_separation[0] / specimen.length_scale) ** 3
    if loading.liquid is not None:  # pressure control: p is the gas's, λ_a and V are measured
        return _gas_readers(space, loading.liquid, nodes, X, R, V0) | {"wall_ratio": lambda level: ratio}

    def pressure(level) -> float:
        u, f = level.evaluation.u, level.evaluation.f_int
        dofs = 3 * nodes[:, None] + np.arange(3)
        x = X + u[dofs]
        lam = float(np.mean(np.linalg.norm(x, axis=1) / R))
        return float(np.sum(f[dofs] * X) / (3.0 * lam * lam * V0))

    return {"pressure": pressure, "wall_ratio": lambda level: ratio}


def _gas_readers(space, liquid, nodes, X, R, V0) -> dict:
    """p = t p*, λ_a = mean |x_i| / |X_i| over the inner nodes, V / V₀ (the prism volume, exact for
    the facetted cavity: vlab.fe.liquid)."""
    from vlab.fe.liquid import enclosed_volume

    points = space.node_coordinates

    def moved(level) -> np.ndarray:
        return points + level.evaluation.u.reshape(-1, 3)

    return {"pressure": lambda level: liquid.pressure(level.t, 0.0),
            "inner_stretch": lambda level: float(np.mean(np.linalg.norm(moved(level)[nodes], axis=1) / R)),
            "volume_ratio": lambda level: enclosed_volume(moved(level), liquid.triangles) / V0}


def pressure_maximum_reason(prepared, failure) -> str | None:
    """The stop of a pressure-controlled inflation, said as what it is: the specimen's pressure
    maximum (no equilibrium at a higher pressure), with the pressure and stretch of the last
    converged state; None if the test is not pressure-controlled (its stop keeps its reason)."""
    from types import SimpleNamespace

    liquid = prepared.loading.liquid
    if liquid is None or liquid.control != "pressure" or failure.u_converged is None:
        return None
    readers = cavity_pressure_readers(prepared.space, prepared.specimen, prepared.loading, prepared.oracle)
    body = prepared.body
    body.set_load(failure.t_converged)
    level = SimpleNamespace(t=failure.t_converged, evaluation=body.evaluate(failure.u_converged))
    p = readers["pressure"](level)
    lam = readers["pole_stretch" if "pole_stretch" in readers else "inner_stretch"](level)
    where = "pole" if "pole_stretch" in readers else "inner hoop"
    return (f"pressure maximum (limit point) of the specimen: under test.control = 'pressure' there is no "
            f"equilibrium above p = {p:.6g} MPa, reached at {where} stretch {lam:.6g} (the last converged state; "
            f"the test asked for p = {liquid.target:.6g} MPa); run test.control = 'volume' to follow the "
            f"curve past it (Newton at the next pressure: {failure.reason})")


def limit_point(stretch, pressure) -> dict | None:
    """The pressure maximum of the recorded rows (module docstring), or None if p only rises or
    peaks at the last row (the maximum may lie beyond the test)."""
    lam, p = np.asarray(stretch, float), np.asarray(pressure, float)
    if len(p) < 3:
        return None
    i = int(np.argmax(p))
    if i == 0 or i == len(p) - 1 or not np.all(np.diff(lam[: i + 2]) > 0):
        return None
    x, y = lam[i - 1:i + 2], p[i - 1:i + 2]
    a, b, c = np.polyfit(x, y, 2)
    if a >= 0:
        return {"stretch": float(lam[i]), "pressure": float(p[i]), "method": "recorded maximum"}
    vertex = -b / (2 * a)
    return {"stretch": float(vertex), "pressure": float(c - b * b / (4 * a)),
            "method": "parabola through the recorded maximum and its neighbours",
            "bracket": [float(x[0]), float(x[2])]}


def inflation_constants(curve, window, method) -> ElasticConstants:
    """The limit point and the initial slope (module docstring)."""
    p = curve.extra.get("pressure", [])
    stretch = curve.extra.get("pole_stretch") or curve.extra.get("inner_stretch") or curve.stretch[0]
    found = limit_point(stretch, p)
    note = ("inflation: E and nu are not measured; the pressure maximum is a property of the balloon "
            "(measured.limit_point)")
    extra: dict = {"limit_point": found}
    if found is None:
        extra["limit_point_note"] = (f"no pressure maximum up to stretch {max(stretch):.4g}"
                                     if curve.t else "no level recorded")
    try:
        fit = fit_line(np.array(stretch) - 1.0, np.array(p), window, method)
        extra |= {"initial_slope": fit.slope, "initial_slope_fit": fit.as_dict()}
    except FitError as exc:
        extra |= {"initial_slope": None, "initial_slope_note": str(exc)}
    if curve.t:
        extra |= {"stretch_at_end": stretch[-1], "pressure_at_end": p[-1] if p else None}
        for key in ("volume_ratio", "pole_height", "pole_stress", "pole_stress_fe"):
            if curve.extra.get(key):
                extra[f"{key}_at_end"] = curve.extra[key][-1]
    return ElasticConstants(None, None, None, None, [{"axis": "r", "limit_point": found}], note, extra)
