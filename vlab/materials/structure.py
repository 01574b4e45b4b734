"""Isotropic tangents as a short sum of outer products of 3×3 fields.

The tangents of the isotropic models here are sums of three kinds of terms (shapes (3,3,*batch);
a Python float s in a ``kron`` slot stands for s·δ):

    kron  (B, C):  A_iJkL += B_ik C_JL          e.g. μ δ_ik δ_JL,  δ_ik S_JL,  μ b_ik δ_JL
    dyad  (P, Q):  A_iJkL += P_iJ Q_kL          e.g. λ F⁻ᵀ ⊗ F⁻ᵀ
    cross (P, Q):  A_iJkL += P_iL Q_kJ          e.g. (μ − λ ln J) F⁻ᵀ_iL F⁻ᵀ_kJ

Stored this way a tangent costs a few 3×3 fields per point instead of 81 numbers, and its pull
back to the reference cell (what the stiffness kernel needs),

    Â_imkn = dx Σ_JL R_mJ A_iJkL R_nL,       R = ∂ξ/∂X,

follows term by term with H = P Rᵀ, H' = Q Rᵀ (3×3 per point):

    kron:  B_ik (R C Rᵀ)_mn dx      dyad:  H_im H'_kn dx      cross:  H_in H'_km dx

so the full (3,3,3,3,e,q) array is never formed. ``full()`` builds it (for the Taylor tests and
any kernel without a reference map): both paths come from the same terms.

The first field of a dyad or cross may be given as ``(c, X)``, meaning c·X with c a float or a
scalar field (*batch): the common case P = c Q (λ F⁻ᵀ ⊗ F⁻ᵀ) then pulls X back once and scales.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

Field = np.ndarray | float


@dataclass
class TangentTerms:
    """A_iJkL = Σ kron B_ik C_JL + Σ dyad P_iJ Q_kL + Σ cross P_iL Q_kJ (MPa)."""

    batch: tuple[int, ...]
    kron: list[tuple[Field, Field]] = field(default_factory=list)
    dyad: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)
    cross: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)

    def full(self) -> np.ndarray:
        """The tangent A, shape (3,3,3,3,*batch), MPa (a new array)."""
        A = np.zeros((3, 3, 3, 3) + self.batch)
        for P, Q in self.dyad:
            P = _scaled(P)
            for i in range(3):
                for J in range(3):
                    A[i, J] += P[i, J] * Q
        for P, Q in self.cross:
            P = _scaled(P)
            for i in range(3):
                for L in range(3):
                    A[i, :, :, L] += P[i, L] * Q.swapaxes(0, 1)
        identity = np.eye(3).reshape((3, 3) + (1,) * len(self.batch))
        for B, C in self.kron:
            C = C * identity if np.isscalar(C) else C
            for i in range(3):
                for k in range(3):
                    if np.isscalar(B):
                        if i == k:
                            A[i, :, k, :] += B * C
                    else:
                        A[i, :, k, :] += B[i, k] * C
        return A

    def pulled_back(self, R: np.ndarray, dx: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Â for the six blocks i ≤ k, layout (p, q, m, n, e) with p over UPPER_PAIRS,
        C-contiguous, dx folded in (N/mm · mm).

        R = ∂ξ_m/∂X_J with shape (m, J, q, e) and dx with shape (q, e), element index last so
        that every operation runs over long contiguous rows; the batch of the terms must be
        (e, q); ``out`` receives Â if given. The blocks i > k follow from the major symmetry Â_imkn = Â_knim (a tangent is the
        second derivative of ψ), so they are never formed. Each output slice (p, m, n) is
        written once while its inputs are in cache."""
        n_qp, n_el = dx.shape
        dyads, crosses, krons, deltas = self._pulled_terms(R, dx)
        Y = np.empty((len(UPPER_PAIRS), n_qp, 3, 3, n_el)) if out is None else out
        scratch = np.empty((n_qp, n_el))
        for p, (i, k) in enumerate(UPPER_PAIRS):
            for m in range(3):
                for n in range(3):
                    if i == k and n < m:                    # Â_imin = Â_inim
                        np.copyto(Y[p, :, m, n], Y[p, :, n, m])
                        continue
                    parts = ([(H[i, :, m], H2[k, :, n]) for H, H2 in dyads]      # H_im H'_kn
                             + [(H[i, :, n], H2[k, :, m]) for H, H2 in crosses]  # H_in H'_km
                             + [(B[i, k], RCR[:, m, n]) for B, RCR in krons])   # B_ik (RCRᵀ)_mn
                    scaled = [RCR[:, m, n] for RCR in deltas] if i == k else []
                    _sum_products(Y[p, :, m, n], parts, scaled, scratch)
        return Y

    def _pulled_terms(self, R: np.ndarray, dx: np.ndarray) -> tuple[list, list, list, list]:
        """The terms pulled back to reference-cell gradients, element index last: (P Rᵀ dx, Q Rᵀ)
        pairs of the dyads and crosses (i, q, m, e), (B, R C Rᵀ dx) of the full krons (q, m, n, e)
        and B R C Rᵀ dx of the scalar ones (B δ_ik); a factor shared by several terms is pulled once."""
        pulls: dict[int, np.ndarray] = {}                                  # id(X) -> X Rᵀ

        def pull(X: np.ndarray) -> np.ndarray:
            if id(X) not in pulls:
                pulls[id(X)] = _pull(X, R)
            return pulls[id(X)]

        def weighted(P) -> np.ndarray:                                     # P Rᵀ dx
            c, X = P if isinstance(P, tuple) else (1.0, P)
            w = dx * (c if np.isscalar(c) else np.asarray(c).T)
            return pull(X) * w[None, :, None, :]

        dyads = [(weighted(P), pull(Q)) for P, Q in self.dyad]            # (i, q, m, e)
        crosses = [(weighted(P), pull(Q)) for P, Q in self.cross]
        krons = [(_batch_last(B), _pull_both(C, R, dx))                    # (q, m, n, e)
                 for B, C in self.kron if not np.isscalar(B)]
        deltas = [B * _pull_both(C, R, dx) for B, C in self.kron if np.isscalar(B)]  # B δ_ik
        return dyads, crosses, krons, deltas

    def isotropic(self) -> "IsotropicTangent | None":
        """These terms as one ``IsotropicTangent`` (what the compiled kernel takes), or None if
        they do not have that form: exactly one dyad and one cross on the same field X (each
        X ⊗ X times a scalar or scalar field), and krons that are s·δ ⊗ δ, δ ⊗ C or B ⊗ δ."""
        if len(self.dyad) != 1 or len(self.cross) != 1:
            return None
        (alpha, X), Q = _coefficient(self.dyad[0][0]), self.dyad[0][1]
        (beta, X2), Q2 = _coefficient(self.cross[0][0]), self.cross[0][1]
        if not (X is Q and X2 is Q and Q2 is Q) or np.ndim(Q) != 2 + len(self.batch):
            return None
        c0, S, B = 0.0, None, None
        for first, second in self.kron:
            if np.isscalar(first) and np.isscalar(second):
                c0 += float(first) * float(second)
            elif np.isscalar(first):
                term = second if first == 1.0 else first * second
                S = term if S is None else S + term
            elif np.isscalar(second):
                term = first if second == 1.0 else second * first
                B = term if B is None else B + term
            else:
                return None
        return IsotropicTangent(X, alpha, beta, c0, S, B)


@dataclass
class IsotropicTangent:
    """A_iJkL = c₀ δ_ik δ_JL + δ_ik S_JL + B_ik δ_JL + α X_iJ X_kL + β X_iL X_kJ (MPa).

    X, S, B are (3,3,*batch) fields (S, B symmetric, or None for zero), α and β floats or
    (*batch) fields, c₀ a float: the tangents of the linear, St. Venant–Kirchhoff and
    Neo-Hookean models (vlab.fe.compiled assembles this form)."""

    X: np.ndarray
    alpha: Field
    beta: Field
    c0: float
    S: np.ndarray | None
    B: np.ndarray | None


def _coefficient(P) -> tuple[Field, np.ndarray]:
    """(c, X) for a dyad/cross first field given as (c, X) or as X (c = 1)."""
    return P if isinstance(P, tuple) else (1.0, P)


#: The (i, k) blocks i ≤ k of a major-symmetric tangent, in the order of ``pulled_back``: the
#: three diagonal blocks (symmetric in (m, n), so their element matrices are symmetric) first.
UPPER_PAIRS = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


def _scaled(P) -> np.ndarray:
    """P, or c·X for P = (c, X)."""
    if not isinstance(P, tuple):
        return P
    c, X = P
    return c * X


def _batch_last(P: np.ndarray) -> np.ndarray:
    """(3,3,e,q) -> (3,3,q,e) contiguous."""
    return np.ascontiguousarray(np.swapaxes(P, 2, 3))


def _sum_products(y: np.ndarray, parts: list, scaled: list, scratch: np.ndarray) -> None:
    """y = Σ a b over the (a, b) in ``parts`` + Σ ``scaled``, in place (``scratch`` holds each product)."""
    if parts:
        np.multiply(*parts[0], out=y)
        for a, b in parts[1:]:
            y += np.multiply(a, b, out=scratch)
    else:
        y.fill(0.0)
    for term in scaled:
        y += term


def _pull(P: np.ndarray, R: np.ndarray) -> np.ndarray:
    """H_im = Σ_J P_iJ R_mJ per point: P (3,3,e,q), R (m,J,q,e) -> H (i,q,m,e)."""
    P = _batch_last(P)
    H = np.empty((3, R.shape[2], 3, R.shape[3]))
    for i in range(3):
        for m in range(3):
            h = H[i, :, m]
            np.multiply(P[i, 0], R[m, 0], out=h)
            h += P[i, 1] * R[m, 1]
            h += P[i, 2] * R[m, 2]
    return H


def _pull_both(C, R: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """(R C Rᵀ)_mn dx per point, C a (3,3,e,q) field or a scalar times δ -> (q, m, n, e)."""
    n_qp, n_el = dx.shape
    out = np.empty((n_qp, 3, 3, n_el))
    CR = R if np.isscalar(C) else None
    if CR is None:                                          # (C Rᵀ)_Jn = Σ_L C_JL R_nL
        C = _batch_last(C)
        CR = np.empty((3, 3, n_qp, n_el))                   # indexed (n, J)
        for n in range(3):
            for J in range(3):
                np.multiply(C[J, 0], R[n, 0], out=CR[n, J])
                CR[n, J] += C[J, 1] * R[n, 1]
                CR[n, J] += C[J, 2] * R[n, 2]
    for m in range(3):
        for n in range(3):
            o = out[:, m, n]
            np.multiply(R[m, 0], CR[n, 0], out=o)
            o += R[m, 1] * CR[n, 1]
            o += R[m, 2] * CR[n, 2]
            o *= dx if not np.isscalar(C) else C * dx
    return out
