"""Kind "confined-compression": the axial stress of a specimen in a frictionless rigid die, the
homogeneous state F = diag(λ, 1, 1), J = λ, of a compressible card:

    P11 = τ1(λ, 1, 1) / λ          (nominal = true here: σ11 = τ1/J and J = λ)

with τ1 vlab.identify.states.principal_tau (the isochoric part at λ̄ = J^(−1/3)(λ, 1, 1) and the
volumetric J U'(J)). It is what fixes K: an incompressible card cannot deform this way, so the
kind needs model.K or model.fit_K. At small strain the slope is the constrained modulus
K + 4μ/3.

Columns: ``stretch`` λ (or ``strain``), ``stress`` (``units``: MPa, kPa, ...), compression < 0.
"""

from __future__ import annotations

import numpy as np

from vlab.identify.datasets import STRESS_UNITS, check_monotonic, check_plausible
from vlab.identify.kinds.base import FitKind
from vlab.identify.states import principal_tau

__all__ = ["KIND", "axial_stress"]


def axial_stress(model, X, stretch):
    """P11 (m, n), MPa, at F = diag(λ, 1, 1) for stretches λ (n,) of internal coordinates X (m, n_x)."""
    c, K = model.split(np.asarray(X)[:, None, :])
    lam = np.asarray(stretch, float)[None, :]
    one = np.ones_like(lam)
    return principal_tau(model, c, K, lam, one, one)[0] / lam + 0.0 * c[0]


def predict(model, X, d):
    return axial_stress(model, X, d.a)


def build(path, cols, wanted, lines, factor, geometry):
    lam, y = cols["stretch"], cols["stress"] * factor
    check_monotonic(path, wanted["stretch"], lam, lines)
    check_plausible(path, "confined-compression", wanted["stretch"], lam, y, lines)
    return lam, None, y, {"geometry": {}, "outputs": ("stress",)}


def max_I1(d) -> float:
    """Ī1 = λ^(−2/3) (λ² + 2), the isochoric I1 of diag(λ, 1, 1)."""
    return float(np.max(d.a ** (-2.0 / 3.0) * (d.a**2 + 2.0)))


def states(d):
    """diag(λ, 1, 1) at each row (J = λ)."""
    lam = np.asarray(d.a, float)
    return np.array([lam, np.ones_like(lam), np.ones_like(lam)])


KIND = FitKind(
    name="confined-compression", columns=(("stretch", "stress"), ()), control="stretch", geometry={},
    units=STRESS_UNITS, default_unit="MPa", measures=("nominal", "true"), compressible=True, build=build,
    predict=predict, max_I1=max_I1, labels=("axial stretch λ", {"stress": "axial stress (MPa)"}), states=states)
