"""Isotropic functions of the principal stretches: stress and tangent from principal quantities.

A potential W(F) that depends on F only through its principal stretches λ_A (A = 1..3), with
F = Σ_A λ_A n_A ⊗ N_A (n_A spatial, N_A referential unit vectors), is written in the principal
log strains ε_A = ln λ_A. The caller supplies, per point,

    τ_A = ∂W/∂ε_A          principal Kirchhoff stress, MPa
    c_AB = ∂τ_A/∂ε_B       principal moduli (the consistent ones for a return map), MPa
    g_AB = (τ_A − τ_B)/(ε_A − ε_B)   for A ≠ B, its limit c_AA − c_AB when ε_A = ε_B, MPa

and this module returns (Ogden 1984, §6.1; with w_A = ∂W/∂λ_A = τ_A/λ_A)

    P = Σ_A w_A n_A ⊗ N_A
    A = Σ_AB w_AB (n_A⊗N_A) ⊗ (n_B⊗N_B)
        + Σ_{A≠B} [ t1_AB (n_A⊗N_B) ⊗ (n_A⊗N_B) + t2_AB (n_A⊗N_B) ⊗ (n_B⊗N_A) ]

    w_AB = (c_AB − δ_AB τ_A)/(λ_A λ_B),   t1 = (a + b)/2,   t2 = (a − b)/2,
    a_AB = (w_A − w_B)/(λ_A − λ_B) = g_AB ℓ_AB/λ_A − τ_B/(λ_A λ_B),  ℓ_AB = (ε_A − ε_B)/(λ_A − λ_B),
    b_AB = (w_A + w_B)/(λ_A + λ_B).

The difference quotient a is evaluated through g and ℓ (ℓ by log1p with its series near
λ_A = λ_B), so equal or nearly equal stretches lose no digits. n_A, N_A and λ_A come from
the symmetric eigenproblem of C = FᵀF (``numpy.linalg.eigh``), n_A = F N_A/λ_A; within a
repeated eigenvalue any orthonormal basis gives the same P and A.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.tensor import dyad

__all__ = ["PrincipalFrame", "principal_frame", "principal_stress", "principal_tangent"]


@dataclass(frozen=True)
class PrincipalFrame:
    """Principal stretches λ (3,*batch), log strains ε (3,*batch), n[i, A] and N[J, A] (3,3,*batch)."""

    lam: np.ndarray
    eps: np.ndarray
    n: np.ndarray
    N: np.ndarray


def principal_frame(F: np.ndarray) -> PrincipalFrame:
    """Principal decomposition F = Σ λ_A n_A ⊗ N_A of a field with det F > 0."""
    C = np.einsum("kI...,kJ...->...IJ", F, F)
    w, V = np.linalg.eigh(C)                         # (*b, 3), (*b, 3, 3): V[..., I, A]
    lam = np.sqrt(np.moveaxis(w, -1, 0))
    N = np.moveaxis(V, (-2, -1), (0, 1))
    n = np.einsum("iJ...,JA...->iA...", F, N) / lam[None]
    return PrincipalFrame(lam=lam, eps=np.log(lam), n=n, N=N)


def principal_stress(frame: PrincipalFrame, tau: np.ndarray) -> np.ndarray:
    """P = Σ_A (τ_A/λ_A) n_A ⊗ N_A, shape (3,3,*batch), MPa."""
    return np.einsum("A...,iA...,JA...->iJ...", tau / frame.lam, frame.n, frame.N)


def _log_quotient(lam: np.ndarray) -> np.ndarray:
    """ℓ_AB = (ln λ_A − ln λ_B)/(λ_A − λ_B), (3,3,*batch); 1/λ at λ_A = λ_B, no cancellation."""
    la, lb = lam[:, None], lam[None, :]
    d = la / lb - 1.0
    small = np.abs(d) < 1e-5
    safe = np.where(small, 1.0, d)
    quotient = np.where(small, 1.0 - d / 2.0 + d * d / 3.0, np.log1p(safe) / safe)  # ln(1+d)/d
    return quotient / lb


def principal_tangent(frame: PrincipalFrame, tau: np.ndarray, c: np.ndarray, g: np.ndarray) -> np.ndarray:
    """A = ∂P/∂F (3,3,3,3,*batch) from τ (3,*b), c (3,3,*b) and g (3,3,*b) (module docstring)."""
    lam, n, N = frame.lam, frame.n, frame.N
    lalb = lam[:, None] * lam[None, :]
    w = (c - np.eye(3).reshape((3, 3) + (1,) * tau[0].ndim) * tau[:, None]) / lalb
    a = g * _log_quotient(lam) / lam[:, None] - tau[None, :] / lalb
    wA = tau / lam
    b = (wA[:, None] + wA[None, :]) / (lam[:, None] + lam[None, :])
    t1, t2 = 0.5 * (a + b), 0.5 * (a - b)
    M = [[n[:, A][:, None] * N[:, B][None, :] for B in range(3)] for A in range(3)]  # n_A ⊗ N_B
    out = np.zeros((3, 3, 3, 3) + tau.shape[1:])
    for A in range(3):
        for B in range(3):
            dyad(w[A, B] * M[A][A], M[B][B], out=out)
            if A != B:
                dyad(t1[A, B] * M[A][B], M[A][B], out=out)
                dyad(t2[A, B] * M[A][B], M[B][A], out=out)
    return out
