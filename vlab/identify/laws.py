"""The identification library: each model in principal stretches, with the card's names (MPa).

Every law returns the principal Kirchhoff-like stresses of its isochoric energy,
w_i = λ_i ∂ψ/∂λ_i (MPa), at stretches λ_1, λ_2, λ_3 (for an incompressible law λ1 λ2 λ3 = 1; a
compressible state passes the isochoric stretches λ̄ = J^(-1/3) λ). Invariant models use
I1 = Σ λ_i², I2 = Σ_{i<j} λ_i² λ_j² and w_i = 2 λ_i² (ψ_1 + ψ_2 (I1 − λ_i²)), ψ_k = ∂ψ/∂I_k:

- neo-hookean    ψ = μ/2 (I1 − 3)                                      mu
- mooney-rivlin  ψ = C10 (I1 − 3) + C01 (I2 − 3)                       C10, C01
- yeoh           ψ = Σ_k C_k0 (I1 − 3)^k, k = 1..3                     C10, C20, C30
- gent           ψ = −μ Jm/2 ln(1 − (I1 − 3)/Jm)                       mu, Jm
- arruda-boyce   ψ = μ Σ_{i=1}^{5} c_i λm^(2−2i) (I1^i − 3^i),          mu, lambda_m
                 c = 1/2, 1/20, 11/1050, 19/7000, 519/673750 (Abaqus' series)
- ogden          ψ = Σ_p 2μ_p/α_p² (λ1^α_p + λ2^α_p + λ3^α_p − 3),     mu = [..], alpha = [..]
                 so w_i = Σ_p 2μ_p/α_p λ_i^α_p

All formulas are written with numpy operations that are analytic in their arguments (no abs,
no max), so a complex parameter or stretch carries its exact derivative (complex step).

Each law fits internal coordinates x with box bounds; the card values are c = T x (T constant),
so derivatives and covariances map exactly (Mooney–Rivlin fits s = C10 + C01 = μ0/2 ≥ 0 and
C01, so that μ0 > 0 is a bound, not a hope).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from vlab.materials.arruda_boyce import LAMBDA_M_MAX

__all__ = ["Law", "LAWS", "law_for", "MODEL_NAMES"]

_AB = np.array([1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750])
_AB_MU0 = np.array([1.0, 3 / 5, 99 / 175, 513 / 875, 42039 / 67375])  # μ0 = μ Σ a_i λm^(2−2i)


def _invariant_w(psi1, psi2, l1, l2, l3):
    """w_i = 2 λ_i² (ψ_1 + ψ_2 (I1 − λ_i²)) for an energy of I1, I2."""
    sq = (l1 * l1, l2 * l2, l3 * l3)
    I1 = sq[0] + sq[1] + sq[2]
    return tuple(2.0 * s * (psi1 + psi2 * (I1 - s)) for s in sq)


def _I1(l1, l2, l3):
    return l1 * l1 + l2 * l2 + l3 * l3


def _nh(c, l1, l2, l3):
    return _invariant_w(0.5 * c[0], 0.0, l1, l2, l3)


def _mr(c, l1, l2, l3):
    return _invariant_w(c[0], c[1], l1, l2, l3)


def _yeoh(c, l1, l2, l3):
    d = _I1(l1, l2, l3) - 3.0
    return _invariant_w(c[0] + 2.0 * c[1] * d + 3.0 * c[2] * d * d, 0.0, l1, l2, l3)


def _gent(c, l1, l2, l3):
    d = _I1(l1, l2, l3) - 3.0
    return _invariant_w(0.5 * c[0] / (1.0 - d / c[1]), 0.0, l1, l2, l3)


def _gent_margin(c, l1, l2, l3):
    """1 − (Ī1 − 3)/Jm: positive below the locking stretch, where ψ_gent is defined."""
    return 1.0 - (_I1(l1, l2, l3) - 3.0) / c[1]


def _arruda_boyce(c, l1, l2, l3):
    I1 = _I1(l1, l2, l3)
    lm2 = c[1] * c[1]
    psi1 = sum(i * _AB[i - 1] * I1 ** (i - 1) / lm2 ** (i - 1) for i in range(1, 6))
    return _invariant_w(c[0] * psi1, 0.0, l1, l2, l3)


def _ogden(c, l1, l2, l3):
    n = len(c) // 2
    coef = [2.0 * c[p] / c[n + p] for p in range(n)]
    out = []
    for lam in (l1, l2, l3):
        ln = np.log(lam)
        out.append(sum(coef[p] * np.exp(c[n + p] * ln) for p in range(n)))
    return tuple(out)


@dataclass(frozen=True)
class Law:
    """One model: card names (flat: "mu[0]"), its w_i, bounds of x and a start sampler.

    ``w(c, l1, l2, l3)``: c is a sequence of card values (each broadcastable with λ).
    ``transform``: c = T x. ``start(rng, scale, stretch_max)`` → (x0, lower, upper) for one start:
    scale is a modulus estimate from the data (MPa), stretch_max the largest I1 seen (Gent's bound).
    ``margin``: for a law defined only below a limit (Gent's chains lock at Ī1 − 3 = Jm), a
    function of (c, λ̄1, λ̄2, λ̄3) that is positive inside the domain; None: defined everywhere.
    """

    model: str
    names: tuple[str, ...]
    w: Callable
    start: Callable
    transform: np.ndarray = field(repr=False, default=None)
    terms: int = 1
    margin: Callable | None = None  # margin(c, λ̄1, λ̄2, λ̄3) > 0 inside the law's domain (Gent)

    def card_values(self, x: np.ndarray) -> np.ndarray:
        """c = T x along the last axis."""
        return x @ self.transform.T

    def canonical_order(self, x: np.ndarray) -> np.ndarray:
        """A permutation of x putting interchangeable terms in one order (Ogden: by α), so that
        equal fits compare equal; entries after the law's own (K) stay in place."""
        idx = np.arange(len(x))
        if self.model != "ogden":
            return idx
        n = self.terms
        order = np.argsort(x[n:2 * n])
        return np.r_[order, n + order, idx[2 * n:]]

    def mu0(self, c) -> float:
        """Initial shear modulus μ0 (MPa) of card values c."""
        c = np.asarray(c, dtype=float)
        if self.model == "neo-hookean":
            return float(c[0])
        if self.model == "mooney-rivlin":
            return float(2 * (c[0] + c[1]))
        if self.model == "yeoh":
            return float(2 * c[0])
        if self.model == "gent":
            return float(c[0])
        if self.model == "arruda-boyce":
            return float(c[0] * sum(a / c[1] ** (2 * i) for i, a in enumerate(_AB_MU0)))
        return float(np.sum(c[: self.terms]))

    def card(self, c) -> dict:
        """The [material] keys of card values c (lists for Ogden), floats rounded to 6 digits."""
        c = [float(f"{v:.6g}") for v in np.asarray(c, dtype=float)]
        if self.model == "ogden":
            n = self.terms
            return {"model": "ogden", "mu": c[:n], "alpha": c[n:]}
        return {"model": self.model, **dict(zip(self.names, c))}


def _log_uniform(rng, lo, hi):
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def _box(x0, lo, hi):
    return np.asarray(x0, float), np.asarray(lo, float), np.asarray(hi, float)


def _start_nh(rng, scale, i1max):
    return _box([_log_uniform(rng, scale / 5, scale * 5)], [1e-12], [np.inf])


def _start_mr(rng, scale, i1max):
    s = _log_uniform(rng, scale / 10, scale)  # C10 + C01 = μ0/2
    return _box([s, rng.uniform(-0.5, 0.5) * s], [1e-12, -np.inf], [np.inf, np.inf])


def _start_yeoh(rng, scale, i1max):
    c10 = _log_uniform(rng, scale / 10, scale)
    return _box([c10, rng.normal(0, 0.05) * c10, rng.normal(0, 0.005) * c10],
                [1e-12, -np.inf, -np.inf], [np.inf] * 3)


def _start_gent(rng, scale, i1max):
    lo_jm = 1.0001 * max(i1max - 3.0, 1e-6)
    return _box([_log_uniform(rng, scale / 5, scale * 5), lo_jm * _log_uniform(rng, 1.2, 50)],
                [1e-12, lo_jm], [np.inf, np.inf])


def _start_ab(rng, scale, i1max):
    return _box([_log_uniform(rng, scale / 5, scale * 5), _log_uniform(rng, 1.5, 20)],
                [1e-12, 1.0001], [np.inf, LAMBDA_M_MAX])  # a card vlab run reads (vlab.materials.arruda_boyce)


def _start_ogden(terms):
    def start(rng, scale, i1max):
        signs = rng.choice([-1.0, 1.0], size=terms, p=[0.3, 0.7])
        signs[0] = 1.0  # at least one stiffening term
        alpha = signs * np.array([_log_uniform(rng, 0.5, 8.0) for _ in range(terms)])
        mu = np.array([_log_uniform(rng, scale / 100, scale) for _ in range(terms)])
        lo = np.r_[np.full(terms, 0.0), np.where(signs > 0, 0.05, -30.0)]
        hi = np.r_[np.full(terms, np.inf), np.where(signs > 0, 30.0, -0.05)]
        return _box(np.r_[mu, alpha], lo, hi)
    return start


def law_for(model: str, terms: int = 1) -> Law:
    """The law of a card model name ("ogden" with ``terms``)."""
    simple = {
        "neo-hookean": (("mu",), _nh, _start_nh),
        "mooney-rivlin": (("C10", "C01"), _mr, _start_mr),
        "yeoh": (("C10", "C20", "C30"), _yeoh, _start_yeoh),
        "gent": (("mu", "Jm"), _gent, _start_gent),
        "arruda-boyce": (("mu", "lambda_m"), _arruda_boyce, _start_ab),
    }
    if model == "ogden":
        names = tuple(f"mu[{p}]" for p in range(terms)) + tuple(f"alpha[{p}]" for p in range(terms))
        return Law("ogden", names, _ogden, _start_ogden(terms), np.eye(2 * terms), terms)
    names, w, start = simple[model]
    T = np.eye(len(names))
    if model == "mooney-rivlin":
        T = np.array([[1.0, -1.0], [0.0, 1.0]])  # C10 = s − C01, C01 = C01
    return Law(model, names, w, start, T, margin=_gent_margin if model == "gent" else None)


MODEL_NAMES = ("neo-hookean", "mooney-rivlin", "yeoh", "gent", "arruda-boyce", "ogden")
LAWS = MODEL_NAMES
