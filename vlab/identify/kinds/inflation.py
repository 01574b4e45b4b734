"""Kind "inflation": the cavity pressure against the inner hoop stretch of an incompressible
thick-walled sphere of inner radius A and wall thickness H (B = A + H), the closed form of
vlab.loading.thick_sphere (Ogden, Non-linear Elastic Deformations, §5.3):

    p(λ_a) = ∫_{λ_b}^{λ_a} Ŵ'(λ) / (λ³ − 1) dλ,   λ_b³ = 1 + (λ_a³ − 1)(A/B)³,
    Ŵ'(λ) = 2 (w1 − w3)/λ at (λ, λ, λ⁻²)        (twice the equibiaxial nominal stress)

summed here by Gauss–Legendre over [λ_b, λ_a] (``NODES`` points, analytic in the card: complex
step), where the loading module integrates one material by adaptive quadrature. The integrand's
0/0 at λ = 1 is removable (Ŵ'(1) = 0). A compressible card enters by its isochoric law. The
pressure passes a maximum (the balloon's limit point), so it is not checked for monotony: only
the stretch is.

Columns: ``stretch`` λ_a (or ``strain``), ``pressure`` (``units``: MPa, kPa, ...);
``[data.geometry] inner_radius`` A and ``thickness`` H (mm).
"""

from __future__ import annotations

import numpy as np

from vlab.fields import SceneError
from vlab.identify.datasets import STRESS_UNITS, check_monotonic, check_plausible
from vlab.identify.kinds.base import FitKind, gauss
from vlab.loading.thick_sphere import outer_stretch

__all__ = ["KIND", "pressure", "wall_ratio"]

NODES = 40
WRONG_SIGN = 0.02


def wall_ratio(geometry: dict) -> float:
    """(A/B)³ with B = A + H."""
    A = geometry["inner_radius"]
    return (A / (A + geometry["thickness"])) ** 3


def pressure(model, X, stretch, ratio: float):
    """p (m, n), MPa, at inner hoop stretches λ_a (n,) of internal coordinates X (m, n_x)."""
    c, _ = model.split(np.asarray(X)[:, None, :])
    s, w = gauss(NODES)
    la = np.asarray(stretch, float)
    lb = outer_stretch(la, ratio)
    lam = (lb[:, None] + (la - lb)[:, None] * s[None, :]).reshape(1, -1)
    wv = model.law.w(c, lam, lam, lam**-2.0)
    den = lam**3 - 1.0
    f = 2.0 * (wv[0] - wv[2]) / lam / np.where(np.abs(den) < 1e-12, 1.0, den)
    m = np.asarray(X).shape[0]
    f = np.broadcast_to(f, (m, lam.shape[1])).reshape(m, len(la), NODES)
    return (f @ w) * (la - lb)[None, :]


def predict(model, X, d):
    return pressure(model, X, d.a, wall_ratio(d.extra["geometry"]))


def build(path, cols, wanted, lines, factor, geometry):
    lam, p = cols["stretch"], cols["pressure"] * factor
    check_monotonic(path, wanted["stretch"], lam, lines)
    check_plausible(path, "inflation", wanted["pressure"], lam, p, lines)  # the size only
    bad = np.nonzero(np.sign(lam - 1.0) * p < -WRONG_SIGN * float(np.max(np.abs(p))))[0]
    if len(bad):
        j = int(bad[0])
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted['pressure']!r}: pressure {p[j]:g} MPa at "
                         f"stretch {lam[j]:g} has the sign opposite to the inflation (check the sign convention)")
    return lam, None, p, {"geometry": geometry, "outputs": ("pressure",)}


def max_I1(d) -> float:
    """I1 = 2 λ_a² + λ_a⁻⁴ at the inner surface, the largest stretch of the wall."""
    return float(np.max(2.0 * d.a**2 + d.a**-4.0))


def states(d):
    """Equibiaxial (λ, λ, λ⁻²) through the wall, λ from λ_b to λ_a at each row."""
    la = np.asarray(d.a, float)
    lb = outer_stretch(la, wall_ratio(d.extra["geometry"]))
    lam = (lb[:, None] + (la - lb)[:, None] * np.linspace(0.0, 1.0, 5)).ravel()
    return np.array([lam, lam, lam**-2.0])


KIND = FitKind(
    name="inflation", columns=(("stretch", "pressure"), ()), control="stretch",
    geometry={"inner_radius": "the sphere's inner radius A", "thickness": "its wall thickness H"},
    units=STRESS_UNITS, default_unit="MPa", measures=(), compressible=False, build=build, predict=predict,
    max_I1=max_I1, labels=("inner hoop stretch λ_a", {"pressure": "pressure (MPa)"}), states=states)
