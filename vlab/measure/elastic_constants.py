"""Young's modulus and Poisson's ratio from a recorded curve, over a stated strain window.

Uniaxial:  E = slope of engineering stress against extensometer strain;
           ν = −slope of transverse strain against extensometer strain (same window).
Biaxial (plane stress in the gauge region):
           ε_t = −ν/(1−ν) (ε_x + ε_y)   ⇒  ν = r/(1+r) with r = −slope(ε_t vs ε_x + ε_y);
           s_x = E/(1−ν²) (ε_x + ν ε_y)  ⇒  E = (1−ν²) slope(s_x vs ε_x + ν ε_y), likewise for y.
The window applies to |strain| of the axis (the larger one for biaxial), so the same window serves
tension and compression.

Cruciform (the curve carries the FE centre averages P̄, ε̄ of the gauge region; the nominal stress
F/A_arm is not the gauge stress there, measure/centre_stress.py). Plane stress in the centre:
           σ_x = E/(1−ν²) (ε_x + ν ε_y),   σ_y = E/(1−ν²) (ε_y + ν ε_x),   ε_z = −ν/(1−ν) (ε_x + ε_y).
- any ratio but equibiaxial: the per-axis readings of one test fix both constants. With
  a = E/(1−ν²), b = ν a the two axes' rows σ_x = c_x + a ε̄_x + b ε̄_y, σ_y = c_y + a ε̄_y + b ε̄_x
  are fitted together (least squares over the window; chord: the end rows' differences), then
  ν = b/a, E = a (1−ν²);
- equibiaxial (ε̄_x and ε̄_y within 5 % over the window): the in-plane rows only fix a + b =
  E/(1−ν), so ν comes from the through-thickness strain, r = −slope(ε̄_z vs ε̄_x + ε̄_y), ν = r/(1+r),
  and E per axis from σ_a against (ε̄_a + ν ε̄_other)/(1−ν²) as for the block.
The lab's figure from extensometers and nominal stress (:func:`nominal_biaxial`) is reported beside
it: it is off by the correction factor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.measure.fit import FitError, LineFit, fit_line
from vlab.measure.recorder import Curve


@dataclass(frozen=True)
class ElasticConstants:
    E: float | None
    nu: float | None
    E_fit: dict | None
    nu_fit: dict | None
    per_axis: list[dict]
    note: str = ""


def elastic_constants(curve: Curve, window: tuple[float, float], method: str) -> ElasticConstants:
    if not curve.t:
        return ElasticConstants(None, None, None, None, [], "not measured: no level was recorded")
    try:
        if len(curve.axes) == 1:
            return _uniaxial(curve, window, method)
        if curve.centre:
            return _centre(curve, window, method)
        return _biaxial(curve, window, method)
    except FitError as exc:
        return ElasticConstants(None, None, None, None, [], f"not measured: {exc}")


def crosshead_modulus(curve: Curve, window, method) -> dict | None:
    """The modulus a lab without an extensometer would report: slope of engineering stress
    against crosshead strain λ_grip − 1 = Δ(grip separation)/(initial grip separation), fitted
    over the same |strain| window (uniaxial tests only). It includes the fillets' and tabs'
    compliance and the grips' lateral constraint, so on a dogbone it is not E."""
    if len(curve.axes) != 1:
        return None
    try:
        fit = fit_line(np.array(curve.stretch[0]) - 1.0, curve.column("stress", 0), window, method)
    except FitError as exc:
        return {"E": None, "fit": None, "note": f"not measured: {exc}"}
    return {"E": fit.slope, "fit": fit.as_dict(), "note": ""}


def nominal_biaxial(curve: Curve, window, method) -> ElasticConstants:
    """E and ν a lab gets from the extensometers, the thickness extensometer and the nominal stress
    F/A0 (the block's biaxial formulas), whatever the specimen."""
    try:
        return _biaxial(curve, window, method)
    except FitError as exc:
        return ElasticConstants(None, None, None, None, [], f"not measured: {exc}")


EQUIBIAXIAL_SPREAD = 0.05  # |ε̄_x − ε̄_y| ≤ this × |ε̄_lead| over the window: treated as equibiaxial


def _centre(curve: Curve, window, method) -> ElasticConstants:
    c = {k: np.array(v) for k, v in curve.centre.items()}
    ex, ey, sx, sy = c["strain_x"], c["strain_y"], c["stress_x"], c["stress_y"]
    lead = ex if np.max(np.abs(ex)) >= np.max(np.abs(ey)) else ey
    inside = (np.abs(lead) >= window[0] * (1 - 1e-9)) & (np.abs(lead) <= window[1] * (1 + 1e-9))
    if inside.sum() < 2:
        raise FitError(f"only {int(inside.sum())} recorded point(s) with |centre strain| in {window}; need at least 2")
    if np.max(np.abs(ex - ey)[inside]) <= EQUIBIAXIAL_SPREAD * np.max(np.abs(lead)[inside]):
        r_fit = _slope_on(lead, ex + ey, c["strain_z"], window, method)
        nu = -r_fit.slope / (1 - r_fit.slope)
        axes = []
        for axis, (own, other, stress) in enumerate(((ex, ey, sx), (ey, ex, sy))):
            fit = _slope_on(lead, (own + nu * other) / (1 - nu**2), stress, window, method)
            axes.append({"axis": "xy"[axis], "E": fit.slope, "nu": nu, "fit": fit.as_dict()})
        E = float(np.mean([a["E"] for a in axes]))
        return ElasticConstants(E, nu, axes[0]["fit"], r_fit.as_dict(), axes,
                                "centre averages, equibiaxial: nu from the through-thickness strain")
    a, b, fit = _in_plane_fit(ex[inside], ey[inside], sx[inside], sy[inside], method)
    nu = b / a
    E = a * (1 - nu**2)
    fit |= {"window": tuple(window), "slope": E}
    return ElasticConstants(E, nu, fit, fit, [{"axis": "xy", "E": E, "nu": nu, "fit": fit}],
                            "centre averages: E and nu from the per-axis readings")


def _in_plane_fit(ex, ey, sx, sy, method) -> tuple[float, float, dict]:
    """a, b of σ_x = c_x + a ε_x + b ε_y, σ_y = c_y + a ε_y + b ε_x (module docstring)."""
    n = len(ex)
    if method == "chord":
        order = np.argsort(np.abs(ex) + np.abs(ey))
        i, j = order[0], order[-1]
        A = np.array([[ex[j] - ex[i], ey[j] - ey[i]], [ey[j] - ey[i], ex[j] - ex[i]]])
        a, b = np.linalg.solve(A, [sx[j] - sx[i], sy[j] - sy[i]])
        return float(a), float(b), {"method": "chord", "n_points": 2, "r2": 1.0, "a": float(a), "b": float(b)}
    one, zero = np.ones(n), np.zeros(n)
    design = np.vstack([np.column_stack([one, zero, ex, ey]), np.column_stack([zero, one, ey, ex])])
    y = np.concatenate([sx, sy])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    resid = y - design @ coef
    centred = np.concatenate([sx - sx.mean(), sy - sy.mean()])
    ss_tot = float(centred @ centred)
    r2 = 1.0 - float(resid @ resid) / ss_tot if ss_tot > 0 else 1.0
    a, b = float(coef[2]), float(coef[3])
    return a, b, {"method": "regression", "n_points": n, "r2": r2, "a": a, "b": b}


def _uniaxial(curve: Curve, window, method) -> ElasticConstants:
    eps = np.array(curve.strain[0])
    e_fit = fit_line(eps, curve.column("stress", 0), window, method)
    nu_fit = fit_line(eps, np.array(curve.transverse_strain), window, method)
    return ElasticConstants(e_fit.slope, -nu_fit.slope, e_fit.as_dict(), nu_fit.as_dict(),
                            [{"axis": "x", "E": e_fit.slope, "nu": -nu_fit.slope}])


def _biaxial(curve: Curve, window, method) -> ElasticConstants:
    ex, ey = np.array(curve.strain[0]), np.array(curve.strain[1])
    lead = ex if np.max(np.abs(ex)) >= np.max(np.abs(ey)) else ey
    # Fit on the leading axis' strain as abscissa so the window selects the same rows.
    r_fit = _slope_on(lead, ex + ey, np.array(curve.thickness_strain), window, method)
    r = -r_fit.slope
    nu = r / (1 + r)
    axes = []
    for axis, (own, other) in enumerate(((ex, ey), (ey, ex))):
        x = (own + nu * other) / (1 - nu**2)
        fit = _slope_on(lead, x, curve.column("stress", axis), window, method)
        axes.append({"axis": "xy"[axis], "E": fit.slope, "nu": nu, "fit": fit.as_dict()})
    E = float(np.mean([a["E"] for a in axes]))
    return ElasticConstants(E, nu, axes[0]["fit"], r_fit.as_dict(), axes)


def _slope_on(selector, x, y, window, method) -> LineFit:
    """Fit y against x over the rows where |selector| lies in the window."""
    inside = (np.abs(selector) >= window[0] * (1 - 1e-9)) & (np.abs(selector) <= window[1] * (1 + 1e-9))
    if inside.sum() < 2:
        raise FitError(f"only {int(inside.sum())} recorded point(s) with |strain| in {window}; need at least 2")
    big = (0.0, np.inf)
    return fit_line(np.asarray(x)[inside], np.asarray(y)[inside], big, method)
