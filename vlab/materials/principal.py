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

Assembly (why it is fast): the nine dyads M_AB = n_A ⊗ N_B are an orthonormal basis of 3×3
tensors, in which A is the sparse 9×9 matrix D with D[AA,BB] = w_AB, D[AB,AB] = t1_AB and
D[AB,BA] = t2_AB. With Q[(iJ),(AB)] = n_iA N_JB (per point, 9×9), A = Q D Qᵀ: two batched
9×9 matrix products (``numpy.matmul``) instead of 21 outer products into (3,3,3,3,*batch).
A right factor R (``principal_tangent(..., right=R)``) gives A_iJkL = Ā_iKkM R_JK R_LM, the
tangent of P = P̄ Rᵀ at fixed R (J2 plasticity's change of frame), by replacing N with R N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PrincipalFrame", "principal_frame", "principal_stress", "principal_tangent", "principal_coefficients"]


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


def principal_coefficients(frame: PrincipalFrame, tau: np.ndarray, c: np.ndarray,
                           g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(w_AB, a_AB, b_AB), each (3,3,*batch), of the module docstring (a through g and ℓ)."""
    lam = frame.lam
    batch = tau.shape[1:]
    lalb = lam[:, None] * lam[None, :]
    w = (c - np.eye(3).reshape((3, 3) + (1,) * len(batch)) * tau[:, None]) / lalb
    a = g * _log_quotient(lam) / lam[:, None] - tau[None, :] / lalb
    wA = tau / lam
    b = (wA[:, None] + wA[None, :]) / (lam[:, None] + lam[None, :])
    return w, a, b


def principal_tangent(frame: PrincipalFrame, tau: np.ndarray, c: np.ndarray, g: np.ndarray,
                      right: np.ndarray | None = None) -> np.ndarray:
    """A = ∂P/∂F (3,3,3,3,*batch) from τ (3,*b), c (3,3,*b) and g (3,3,*b) (module docstring);
    with ``right`` R (3,3,*b): A_iJkL = Ā_iKkM R_JK R_LM."""
    lam, n, N = frame.lam, frame.n, frame.N
    batch = tau.shape[1:]
    w, a, b = principal_coefficients(frame, tau, c, g)
    t1, t2 = 0.5 * (a + b), 0.5 * (a - b)
    size = int(np.prod(batch, dtype=int))
    D = np.zeros((size, 3, 3, 3, 3))  # D[p, A, B, C, D] over the basis M_AB ⊗ M_CD
    for A in range(3):
        for B in range(3):
            D[:, A, A, B, B] = w[A, B].reshape(size)
            if A != B:
                D[:, A, B, A, B] = t1[A, B].reshape(size)
                D[:, A, B, B, A] = t2[A, B].reshape(size)
    if right is not None:
        N = np.einsum("JK...,KB...->JB...", right, N)
    n_p = np.moveaxis(n.reshape(3, 3, size), -1, 0)  # (p, i, A)
    N_p = np.moveaxis(N.reshape(3, 3, size), -1, 0)  # (p, J, B)
    Q = (n_p[:, :, None, :, None] * N_p[:, None, :, None, :]).reshape(size, 9, 9)  # [(iJ), (AB)]
    A9 = np.matmul(np.matmul(Q, D.reshape(size, 9, 9)), np.swapaxes(Q, 1, 2))
    return np.ascontiguousarray(np.moveaxis(A9.reshape(size, 3, 3, 3, 3), 0, -1)).reshape((3, 3, 3, 3) + batch)
