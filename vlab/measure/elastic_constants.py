"""Young's modulus and Poisson's ratio from a recorded curve, over a stated strain window.

Uniaxial:  E = slope of engineering stress against extensometer strain;
           ν = −slope of transverse strain against extensometer strain (same window).
Biaxial (plane stress in the gauge region):
           ε_t = −ν/(1−ν) (ε_x + ε_y)   ⇒  ν = r/(1+r) with r = −slope(ε_t vs ε_x + ε_y);
           s_x = E/(1−ν²) (ε_x + ν ε_y)  ⇒  E_x = (1−ν²) slope(s_x vs ε_x + ν ε_y), likewise for y;
           E = Σ_a w_a E_a / Σ_a w_a, w_a = Σ (ξ_a − ξ̄_a)² the spread of the abscissa
           ξ_a = (ε_a + ν ε_b)/(1−ν²) (the least-squares slope of both axes stacked, one intercept
           each; chord: w_a = Δξ_a²). An axis whose stress hardly changes (σ_y ≡ 0 when
           ε_y = −ν ε_x) carries no information on E and gets no weight, instead of halving it.
The window applies to |strain| of the axis (the larger one for biaxial), so the same window serves
tension and compression.

Cruciform (the curve carries the FE centre averages P̄_aa, ε̄_aa (a = x, y, z) of the gauge region;
the nominal stress F/A_arm is not the gauge stress there, measure/centre_stress.py). Isotropic
linear elasticity holds between averages over one region, with no plane-stress assumption:
           σ_a = λ (ε_x + ε_y + ε_z) + 2μ ε_a,        a = x, y, z,
fitted for λ, μ over the window (the three rows of every reading stacked; regression with one
intercept per row kind, or chord: the end readings' differences), then
           E = μ (3λ + 2μ)/(λ + μ),   ν = λ / (2 (λ + μ)).
Any ratio, equibiaxial included, fixes both (ε_z differs from ε_x, ε_y). With σ_z = 0 (plane
stress) the z row gives ε_z = −ν/(1−ν)(ε_x + ε_y) and the x, y rows become the lab's
σ_x = E/(1−ν²)(ε_x + ν ε_y), σ_y = E/(1−ν²)(ε_y + ν ε_x); on a thin plate that assumption costs
~0.2 % (σ̄_z/σ̄_x ~ 2e-3), in a thinned pocket ~1 % (σ̄_z/σ̄_x ~ 9e-3), which is why the z row is kept.
The lab's figure from extensometers and nominal stress (:func:`nominal_biaxial`) is reported beside
it: it is off by the correction factor.
"""

from __future__ import annotations

from dataclasses import dataclass, field

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
    extra: dict = field(default_factory=dict)  # a kind's own measures (planar modulus, G, N1), results.json → measured


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
                 area0=dict(curve.area0), time=curve.time[:n], kind=curve.kind,
                 extra={k: v[:n] for k, v in curve.extra.items()}, slip=curve.slip)


def elastic_constants(curve: Curve, window: tuple[float, float], method: str) -> ElasticConstants:
    """What the curve's test kind measures (its ``fit``: vlab/measure/kinds.py) over the window."""
    from vlab.loading.kinds import kind_of
    from vlab.measure.kinds import measure  # the table of fits imports this module

    if not curve.t:
        return ElasticConstants(None, None, None, None, [], "not measured: no level was recorded")
    return measure(kind_of(curve.kind), curve, window, method)


def uniaxial_constants(curve: Curve, window, method) -> ElasticConstants:
    """E and ν of a uniaxial test (module docstring)."""
    try:
        return _uniaxial(curve, window, method)
    except FitError as exc:
        return ElasticConstants(None, None, None, None, [], f"not measured: {exc}")


def biaxial_constants(curve: Curve, window, method) -> ElasticConstants:
    """E and ν of a biaxial test: from the centre averages on a cruciform, else the block's
    plane-stress relations (module docstring)."""
    try:
        return _centre(curve, window, method) if curve.centre else _biaxial(curve, window, method)
    except FitError as exc:
        return ElasticConstants(None, None, None, None, [], f"not measured: {exc}")


def crosshead_modulus(curve: Curve, window, method) -> dict | None:
    """The modulus a lab without an extensometer would report: slope of engineering stress
    against crosshead strain Δ(grip separation)/(initial grip separation) = λ_grip − 1 + C F/L_grip
    (C F the slip in the grips, Curve.crosshead_strain), fitted over the same |strain| window
    (uniaxial tests: vlab.loading.kinds.uniaxial). It includes the fillets' and tabs' compliance,
    the grips' lateral constraint and their slip, so on a dogbone it is not E."""
    try:
        fit = fit_line(curve.crosshead_strain(0), curve.column("stress", 0), window, method)
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


def _centre(curve: Curve, window, method) -> ElasticConstants:
    c = {k: np.array(v) for k, v in curve.centre.items()}
    eps = np.array([c["strain_x"], c["strain_y"], c["strain_z"]])
    sig = np.array([c["stress_x"], c["stress_y"], c["stress_z"]])
    lead = np.max(np.abs(eps[:2]), axis=0)
    inside = (lead >= window[0] * (1 - 1e-9)) & (lead <= window[1] * (1 + 1e-9))
    if inside.sum() < 2:
        raise FitError(f"only {int(inside.sum())} recorded point(s) with |centre strain| in {window}; need at least 2")
    lam, mu, fit = _lame_fit(eps[:, inside], sig[:, inside], method)
    E = mu * (3 * lam + 2 * mu) / (lam + mu)
    nu = lam / (2 * (lam + mu))
    fit |= {"window": tuple(window), "slope": E, "lambda": lam, "mu": mu}
    return ElasticConstants(E, nu, fit, fit, [{"axis": "xyz", "E": E, "nu": nu, "fit": fit}],
                            "centre averages of the gauge region: sigma_a = lambda tr(eps) + 2 mu eps_a, a = x, y, z")


def _lame_fit(eps: np.ndarray, sig: np.ndarray, method: str) -> tuple[float, float, dict]:
    """λ, μ of σ_a = c_a + λ tr ε + 2μ ε_a over readings eps, sig (3, n) (module docstring)."""
    trace = eps.sum(axis=0)
    if method == "chord":
        i, j = np.argsort(np.max(np.abs(eps[:2]), axis=0))[[0, -1]]
        A = np.column_stack([np.full(3, trace[j] - trace[i]), 2 * (eps[:, j] - eps[:, i])])
        (lam, mu), *_ = np.linalg.lstsq(A, sig[:, j] - sig[:, i], rcond=None)
        return float(lam), float(mu), {"method": "chord", "n_points": 2, "r2": 1.0}
    n = eps.shape[1]
    rows = []
    for a in range(3):
        intercepts = np.zeros((n, 3))
        intercepts[:, a] = 1.0
        rows.append(np.column_stack([intercepts, trace, 2 * eps[a]]))
    design, y = np.vstack(rows), sig.ravel()
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    resid = y - design @ coef
    centred = (sig - sig.mean(axis=1, keepdims=True)).ravel()
    ss_tot = float(centred @ centred)
    r2 = 1.0 - float(resid @ resid) / ss_tot if ss_tot > 0 else 1.0
    return float(coef[3]), float(coef[4]), {"method": "regression", "n_points": n, "r2": r2}


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
    axes, weights = [], []
    for axis, (own, other) in enumerate(((ex, ey), (ey, ex))):
        x = (own + nu * other) / (1 - nu**2)
        fit = _slope_on(lead, x, curve.column("stress", axis), window, method)
        axes.append({"axis": "xy"[axis], "E": fit.slope, "nu": nu, "fit": fit.as_dict()})
        weights.append(_spread(lead, x, window, method))
    if sum(weights) <= 0.0:
        raise FitError(f"neither axis' strain varies inside the window {window}")
    E = float(np.dot(weights, [a["E"] for a in axes]) / sum(weights))
    return ElasticConstants(E, nu, axes[0]["fit"], r_fit.as_dict(), axes)


def _spread(selector, x, window, method) -> float:
    """The weight of an axis in the joint modulus: Σ (x − x̄)² over the window (chord: Δx²)."""
    xs = np.asarray(x)[_inside(selector, window)]
    if method == "chord":
        order = np.argsort(np.abs(xs))  # the chord's end points, as fit_line picks them
        return float((xs[order[-1]] - xs[order[0]]) ** 2)
    return float(np.sum((xs - xs.mean()) ** 2))


def _inside(selector, window) -> np.ndarray:
    return (np.abs(selector) >= window[0] * (1 - 1e-9)) & (np.abs(selector) <= window[1] * (1 + 1e-9))


def _slope_on(selector, x, y, window, method) -> LineFit:
    """Fit y against x over the rows where |selector| lies in the window."""
    inside = _inside(selector, window)
    if inside.sum() < 2:
        raise FitError(f"only {int(inside.sum())} recorded point(s) with |strain| in {window}; need at least 2")
    big = (0.0, np.inf)
    return fit_line(np.asarray(x)[inside], np.asarray(y)[inside], big, method)
