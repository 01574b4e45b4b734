"""The fitted Prony series (``[model] viscoelastic``) and the homogeneous history of vlab's
viscoelastic effect (vlab.materials.viscoelastic), written for the complex step.

    viscoelastic = { terms = 2 }              # fit beta_i and tau_i (1..6 terms)
    viscoelastic = { tau = [0.1, 1.0, 10.0] } # tau_i fixed (s), fit beta_i only

The effect's Maxwell branches are isochoric Neo-Hookean branches of shear modulus β_i μ0 (μ0 the
ground law's initial shear modulus). In an incompressible homogeneous state F = diag(λ1, λ2, λ3)
(uniaxial λ, λ^(−1/2), λ^(−1/2); equibiaxial λ, λ, λ^(−2); planar λ, 1, 1/λ) the isochoric
stress is diagonal, S_iso,i = μ0 (1 − I1 / (3 λ_i²)), and the branch stresses follow the
effect's midpoint rule (Holzapfel eq. 6.166), step n → n+1 of Δt = t_{n+1} − t_n:

    ξ_i = exp(−Δt / 2τ_i),    Q_i^{n+1} = ξ_i (ξ_i Q_i^n − β_i S_iso^n) + β_i ξ_i S_iso^{n+1},

from rest (Q = 0, S_iso = 0 at λ = 1, t = 0) — the same recursion, step for step, that `vlab run`
integrates at each quadrature point. The nominal stress along 1 with the free (traction-free)
direction f carrying the Lagrange pressure is

    P_1 = (w_1 − w_f) / λ1 + (λ1² ΣQ_1 − λ_f² ΣQ_f) / λ1     (MPa, w_i = λ_i ∂ψ∞/∂λ_i).

Small-strain dynamic moduli of the same series (DMA; ω = 2π f, G = shear, E = 3 G incompressible):

    G'(ω) = μ0 (1 + Σ β_i ω²τ_i² / (1 + ω²τ_i²)),   G''(ω) = μ0 Σ β_i ω τ_i / (1 + ω²τ_i²).

Every operation is analytic, so a complex parameter carries its exact derivative through the
whole history (jacobian.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table

__all__ = ["PronySpec", "parse_viscoelastic", "history_stress", "branch_stress", "dynamic_moduli", "mu0_of",
           "principal", "without_mullins"]

MAX_TERMS = 6
_AB_MU0 = (1.0, 3 / 5, 99 / 175, 513 / 875, 42039 / 67375)


@dataclass(frozen=True)
class PronySpec:
    terms: int
    tau: tuple[float, ...] | None = None  # fixed relaxation times (s); None: fitted

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"beta[{i}]" for i in range(self.terms)) + (
            tuple(f"tau[{i}]" for i in range(self.terms)) if self.tau is None else ())

    def split(self, X):
        """(β, τ), each (m, N), from the trailing entries of X (m, n_x)."""
        N = self.terms
        if self.tau is None:
            return X[:, -2 * N:-N], X[:, -N:]
        return X[:, -N:], np.broadcast_to(np.asarray(self.tau, float), (X.shape[0], N))


def parse_viscoelastic(raw) -> PronySpec | None:
    if raw is None:
        return None
    t = Table("model.viscoelastic", raw, ("terms", "tau"))
    if ("terms" in t.raw) == ("tau" in t.raw):
        raise SceneError("model.viscoelastic needs terms = N (fit beta_i and tau_i) or tau = [..] (s, fixed; "
                         "fit beta_i only), exactly one of them")
    if "terms" in t.raw:
        return PronySpec(t.integer("terms", 1, MAX_TERMS))
    tau = t.get("tau")
    if not isinstance(tau, list) or not 1 <= len(tau) <= 20:
        raise SceneError(f"model.viscoelastic.tau must be a list of 1..20 relaxation times (s), got {fields.show(tau)}")
    vals = tuple(fields.number(f"model.viscoelastic.tau[{i}]", v, gt=0, le=1e9) for i, v in enumerate(tau))
    if len(set(vals)) != len(vals):
        raise SceneError("model.viscoelastic.tau: the relaxation times must differ (equal ones cannot be told apart)")
    return PronySpec(len(vals), vals)


def mu0_of(law, c):
    """The ground law's initial shear modulus μ0 (MPa) of card values c, analytic (complex-safe)."""
    if law.model in ("neo-hookean", "gent"):
        return c[0]
    if law.model == "mooney-rivlin":
        return 2.0 * (c[0] + c[1])
    if law.model == "yeoh":
        return 2.0 * c[0]
    if law.model == "arruda-boyce":
        return c[0] * sum(a / c[1] ** (2 * i) for i, a in enumerate(_AB_MU0))
    return sum(c[: law.terms])


def principal(kind: str, lam):
    """(λ1, λ2, λ3, free index) of an incompressible homogeneous state of a kind."""
    lam = np.asarray(lam, float)
    if kind == "uniaxial":
        return lam, lam ** -0.5, lam ** -0.5, 1
    if kind == "equibiaxial":
        return lam, lam, lam ** -2.0, 2
    return lam, np.ones_like(lam), 1.0 / lam, 2


def without_mullins(X, effects: dict):
    """The parameter rows without the trailing Mullins entries (x = [law, Prony, Mullins]), so the
    Prony series reads its β, τ from the end of what is left."""
    mullins = effects.get("mullins")
    X = np.asarray(X)
    return X if mullins is None else X[..., :X.shape[-1] - len(mullins.names)]


def history_stress(model, prony: PronySpec | None, X, kind: str, t, lam):
    """Nominal stress P_1 (m, n) along the record's history (t s, λ), rest at t = 0, λ = 1."""
    X = np.asarray(X)
    c, _ = model.split(X[:, None, :])
    l1, l2, l3, f = principal(kind, lam)
    w = model.law.w(c, l1[None, :], l2[None, :], l3[None, :])
    P = (w[0] - w[f]) / l1[None, :] + 0.0 * c[0]
    return P if prony is None else P + branch_stress(model, prony, X, kind, t, lam)


def branch_stress(model, prony: PronySpec, X, kind: str, t, lam):
    """The Maxwell branches' part of P_1 (m, n): (λ1² ΣQ_1 − λ_f² ΣQ_f)/λ1 (module docstring)."""
    X = np.asarray(X)
    c, _ = model.split(X[:, None, :])
    l1, l2, l3, f = principal(kind, lam)
    lf = (l1, l2, l3)[f]
    beta, tau = prony.split(X)
    mu = mu0_of(model.law, [ci[:, 0] for ci in c])[:, None]
    I1 = l1 * l1 + l2 * l2 + l3 * l3
    S1 = mu * (1.0 - I1 / (3.0 * l1 * l1))[None, :]   # (m, n)
    Sf = mu * (1.0 - I1 / (3.0 * lf * lf))[None, :]
    dt = np.diff(np.r_[0.0, np.asarray(t, float)])
    Q1 = np.zeros_like(beta * mu)
    Qf = np.zeros_like(Q1)
    s1p = sfp = 0.0
    out = np.empty((X.shape[0], len(dt)), dtype=np.result_type(X, beta, tau, mu))
    for k in range(len(dt)):
        xi = np.exp(-dt[k] / (2.0 * tau))
        Q1 = xi * (xi * Q1 - beta * s1p) + beta * xi * S1[:, k:k + 1]
        Qf = xi * (xi * Qf - beta * sfp) + beta * xi * Sf[:, k:k + 1]
        s1p, sfp = S1[:, k:k + 1], Sf[:, k:k + 1]
        out[:, k] = (l1[k] ** 2 * Q1.sum(axis=1) - lf[k] ** 2 * Qf.sum(axis=1)) / l1[k]
    return out


def dynamic_moduli(model, prony: PronySpec, X, frequency, modulus: str = "tensile"):
    """(storage, loss), each (m, n) MPa, at frequencies (Hz): E = 3G (tensile) or G (shear)."""
    X = np.asarray(X)
    c, _ = model.split(X)
    mu = mu0_of(model.law, c)[:, None]
    beta, tau = prony.split(X)
    wt = 2.0 * np.pi * np.asarray(frequency, float)[None, :, None] * tau[:, None, :]
    b = beta[:, None, :]
    g1 = mu * (1.0 + np.sum(b * wt * wt / (1.0 + wt * wt), axis=-1))
    g2 = mu * np.sum(b * wt / (1.0 + wt * wt), axis=-1)
    k = 3.0 if modulus == "tensile" else 1.0
    return k * g1, k * g2
