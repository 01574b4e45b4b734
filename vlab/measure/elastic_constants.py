"""Young's modulus and Poisson's ratio from a recorded curve, over a stated strain window.

Uniaxial:  E = slope of engineering stress against extensometer strain;
           ν = −slope of transverse strain against extensometer strain (same window).
Biaxial (plane stress in the gauge region):
           ε_t = −ν/(1−ν) (ε_x + ε_y)   ⇒  ν = r/(1+r) with r = −slope(ε_t vs ε_x + ε_y);
           s_x = E/(1−ν²) (ε_x + ν ε_y)  ⇒  E = (1−ν²) slope(s_x vs ε_x + ν ε_y), likewise for y.
The window applies to |strain| of the axis (the larger one for biaxial), so the same window serves
tension and compression.
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


def first_loading(curve: Curve) -> Curve:
    """The rows of the first ramp (load parameter rising), where the modulus window lies: E and
    ν are the material's virgin small-strain constants, so the unloading and later cycles of a
    load-unload or cyclic test (softened, plastically set or viscous) are not fitted."""
    t = np.asarray(curve.t)
    falling = np.flatnonzero(np.diff(t) <= 0.0)
    n = len(t) if not len(falling) else int(falling[0]) + 1
    return Curve(t=curve.t[:n], stretch={a: v[:n] for a, v in curve.stretch.items()},
                 force={a: v[:n] for a, v in curve.force.items()},
                 strain={a: v[:n] for a, v in curve.strain.items()},
                 transverse_strain=curve.transverse_strain[:n], thickness_strain=curve.thickness_strain[:n],
                 area0=dict(curve.area0), time=curve.time[:n])


def elastic_constants(curve: Curve, window: tuple[float, float], method: str) -> ElasticConstants:
    if not curve.t:
        return ElasticConstants(None, None, None, None, [], "not measured: no level was recorded")
    try:
        if len(curve.axes) == 1:
            return _uniaxial(curve, window, method)
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
