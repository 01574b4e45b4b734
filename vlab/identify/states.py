"""Homogeneous stress responses of the test kinds in principal stretches (MPa).

A fitted ``Constitutive`` is a law (vlab.identify.laws) plus its bulk behaviour: incompressible,
or compressible with the bulk modulus K (fixed or fitted, MPa) and a volumetric energy U(J):
quadratic K/2 (J−1)², log K/2 ln²J, simo-taylor K/4 (J² − 1 − 2 ln J). Principal Kirchhoff
stresses (MPa):

- incompressible: τ_i = w_i − w_f, the Lagrange pressure set by the free (traction-free)
  direction f, at λ_f from λ1 λ2 λ3 = 1;
- compressible:   τ_i = w̄_i − (w̄1 + w̄2 + w̄3)/3 + J U'(J), w̄ at λ̄ = J^(−1/3) λ, and the free
  stretch λ_f solved from τ_f = 0 by Newton (run in complex arithmetic, so that a complex-step
  parameter derivative flows through the converged root exactly);
- "neo-hookean" with K is vlab's own compressible form, ψ = μ/2 (I1 − 3) − μ ln J + λ_L/2 ln²J
  with λ_L = K − 2μ/3: τ_i = μ (λ_i² − 1) + λ_L ln J.

Kinds (λ the controlled stretch, nominal P_i = τ_i/λ_i, true σ_i = τ_i/J):
uniaxial F = diag(λ, t, t); equibiaxial diag(λ, λ, t); planar (pure shear) diag(λ, 1, t);
biaxial diag(λ1, λ2, t) (two stresses); simple shear F = 1 + γ e1⊗e2 (isochoric), principal
stretches λ± = √(1 + γ²/4) ± γ/2 and shear stress σ12 = P12 = (τ1 − τ2)/√(4 + γ²);
volumetric (hydrostatic, compressible only): λ_i = J^(1/3), the pressure p = −τ/J (MPa, positive
in compression; the isochoric part vanishes, so p = −U'(J), or for vlab's Neo-Hookean
−(μ (J^(2/3) − 1) + λ_L ln J)/J).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.identify.laws import Law

__all__ = ["Constitutive", "KINDS", "response", "principal_tau", "incompressible_rows"]

KINDS = ("uniaxial", "equibiaxial", "planar", "biaxial", "simple-shear", "volumetric")
_FREE = {"uniaxial": 1, "equibiaxial": 2, "planar": 2, "biaxial": 2}


@dataclass(frozen=True)
class Constitutive:
    """A law and its bulk: ``bulk`` = "incompressible" | "fixed" | "fit" (K is then x's last entry).
    ``K_over_mu``: the K = K_over_mu · μ0 an incompressible fit's card carries (vlab.identify.card)."""

    law: Law
    bulk: str = "incompressible"
    K: float | None = None
    volumetric: str = "quadratic"
    K_over_mu: float = 1000.0

    @property
    def names(self) -> tuple[str, ...]:
        return self.law.names + (("K",) if self.bulk == "fit" else ())

    def split(self, x):
        """(card values c as a list of columns, K) of internal coordinates x (..., n_x)."""
        n = len(self.law.names)
        c = x[..., :n] @ self.law.transform.T
        K = x[..., n] if self.bulk == "fit" else self.K
        return [c[..., j] for j in range(n)], K

    def card_vector(self, x: np.ndarray) -> np.ndarray:
        """Card values (and K when fitted) of real x, flat."""
        c, K = self.split(np.asarray(x, float))
        return np.array(c + ([K] if self.bulk == "fit" else []), dtype=float)

    @property
    def transform(self) -> np.ndarray:
        """T with card_vector(x) = T x."""
        T = self.law.transform
        if self.bulk == "fit":
            T = np.block([[T, np.zeros((len(T), 1))], [np.zeros((1, len(T))), np.ones((1, 1))]])
        return T


def _dU(vol: str, K, J):
    """J U'(J) of the volumetric energy (MPa)."""
    if vol == "quadratic":
        return K * J * (J - 1.0)
    if vol == "log":
        return K * np.log(J)
    return 0.5 * K * (J * J - 1.0)


def principal_tau(model: Constitutive, c, K, l1, l2, l3):
    """Compressible principal Kirchhoff stresses τ1, τ2, τ3 (MPa)."""
    J = l1 * l2 * l3
    if model.law.model == "neo-hookean":
        mu, lamL = c[0], K - 2.0 * c[0] / 3.0
        return tuple(mu * (lam * lam - 1.0) + lamL * np.log(J) for lam in (l1, l2, l3))
    s = J ** (-1.0 / 3.0)
    w = model.law.w(c, s * l1, s * l2, s * l3)
    mean = (w[0] + w[1] + w[2]) / 3.0
    p = _dU(model.volumetric, K, J)
    return tuple(wi - mean + p for wi in w)


def _stretches(kind: str, a, b, t):
    if kind == "uniaxial":
        return a, t, t
    if kind == "equibiaxial":
        return a, a, t
    if kind == "planar":
        return a, 1.0 + 0.0 * a, t
    return a, b, t


def _incompressible_t(kind: str, a, b):
    return {"uniaxial": lambda: a ** -0.5, "equibiaxial": lambda: a ** -2.0,
            "planar": lambda: 1.0 / a}.get(kind, lambda: 1.0 / (a * b))()


def _solve_free(model, c, K, kind, a, b):
    """The free stretch t with τ_f = 0 (Newton; the iteration slope from a real difference
    quotient only steers the iteration, the converged complex root carries the derivative)."""
    f = _FREE[kind]
    t = _incompressible_t(kind, a, b) * (1.0 + 0j)

    def g(tt):
        return principal_tau(model, c, K, *_stretches(kind, a, b, tt))[f]

    for _ in range(80):
        gt = g(t)
        tr = np.real(t)
        d = np.real(g(tr * (1 + 1e-7)) - g(tr)) / (tr * 1e-7)
        step = gt / d
        t_new = t - step
        t = np.where(np.real(t_new) > 0, t_new, 0.5 * t)
        if np.all(np.abs(step) <= 1e-15 * np.abs(t)):
            break
    return t


def incompressible_rows(kind: str, a, b=None, measure: str = "nominal"):
    """Every incompressible prediction as (w1 − w3)(λ1, λ2, λ3) · g: rows (λ1, λ2, λ3, g).

    Uniaxial has λ2 = λ3 (so w2 = w3); simple shear is written with the principal stretches
    reordered (λ+, 1, λ−) and g = 1/√(4 + γ²); biaxial's second stress is the row with λ1 and
    λ2 swapped. g = 1/λ1 for nominal stress, 1 for true stress.
    """
    a = np.asarray(a, float)
    if kind == "simple-shear":
        lp = np.sqrt(1.0 + 0.25 * a * a) + 0.5 * a
        return lp, np.ones_like(a), 1.0 / lp, 1.0 / np.sqrt(4.0 + a * a)
    if kind == "biaxial":
        b = np.asarray(b, float)
        l1, l2 = np.r_[a, b], np.r_[b, a]
    else:
        l1, l2 = a, {"uniaxial": a ** -0.5, "equibiaxial": a, "planar": np.ones_like(a)}[kind]
    l3 = 1.0 / (l1 * l2)
    return l1, l2, l3, (1.0 / l1 if measure == "nominal" else np.ones_like(l1))


def response(model: Constitutive, x, kind: str, a, b=None, measure: str = "nominal"):
    """Predicted stress (MPa) at controlled stretches a (and b: biaxial λ2) or shears a.

    x: internal coordinates (m, n_x), real or complex; a, b: (n,). Returns (m, n), or (m, 2n)
    for biaxial (stress along 1, then along 2).
    """
    c, K = model.split(np.asarray(x)[:, None, :])
    a = np.asarray(a, float)[None, :]
    b = None if b is None else np.asarray(b, float)[None, :]
    if kind == "volumetric":
        lam = a ** (1.0 / 3.0)
        return -principal_tau(model, c, K, lam, lam, lam)[0] / a + 0.0 * c[0]
    if kind == "simple-shear" or model.bulk == "incompressible":  # J = 1: no bulk term
        l1, l2, l3, g = incompressible_rows(kind, a[0], None if b is None else b[0], measure)
        w = model.law.w(c, l1[None, :], l2[None, :], l3[None, :])
        return (w[0] - w[2]) * g[None, :] + 0.0 * c[0]
    else:
        t = _solve_free(model, c, K, kind, a, b)
        lams = _stretches(kind, a, b, t)
        tau = list(principal_tau(model, c, K, *lams))
        J = lams[0] * lams[1] * lams[2]
    div = (lambda i: lams[i]) if measure == "nominal" else (lambda i: J)
    out = tau[0] / div(0) + 0.0 * c[0]
    if kind == "biaxial":
        out = np.concatenate([out, tau[1] / div(1) + 0.0 * c[0]], axis=-1)
    return out
