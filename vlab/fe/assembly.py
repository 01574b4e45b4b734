"""Vectorized assembly of the total energy, internal force and tangent stiffness.

Material and mesh meet here and nowhere else. Per Newton iteration F, P and A are evaluated once
at all quadrature points; element contributions are formed with batched tensor contractions and
scattered into a sparsity pattern that is computed once per mesh (and once per set of grips).

    W(u)      = Σ_e Σ_q ψ(F_eq) dx_eq                                     (mJ = N·mm)
    f_int[ai] = Σ_e Σ_q P_iJ dN_a,J dx                                     (N)
    K[ai,bk]  = Σ_e Σ_q dN_a,J A_iJkL dN_b,L dx                             (N/mm)
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from vlab.fe.space import DisplacementSpace


@dataclass(frozen=True)
class SparsityPattern:
    """CSR pattern of the global stiffness and the map from element entries to CSR slots.

    Element matrices come in the block layout (i, k, e, a, b) of ``element_stiffness``: the
    entry couples global DOF d·node[e,a] + i to d·node[e,b] + k (d = dim, 3 or 2). ``slot`` gives the CSR data
    index of every such entry, so assembly is one weighted ``bincount``.
    """

    n: int
    indptr: np.ndarray
    indices: np.ndarray
    slot: np.ndarray  # (d² · n_elements · n_local²,) CSR data index of every element entry
    element_shape: tuple[int, int] = (0, 0)  # (n_elements, n_local)

    @classmethod
    def build(cls, element_nodes: np.ndarray, dim: int = 3) -> "SparsityPattern":
        n_el, n_loc = element_nodes.shape
        n = dim * (int(element_nodes.max()) + 1)
        comp = np.arange(dim)
        rows = dim * element_nodes[None, None, :, :, None] + comp[:, None, None, None, None]
        cols = dim * element_nodes[None, None, :, None, :] + comp[None, :, None, None, None]
        rows, cols = np.broadcast_arrays(rows, cols)
        keys, slot = np.unique(rows.astype(np.int64).ravel() * n + cols.ravel(), return_inverse=True)
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(keys // n, minlength=n), out=indptr[1:])
        return cls(n, indptr, (keys % n).astype(np.int32), slot.astype(np.intp), (n_el, n_loc))

    def matrix(self, element_matrices: np.ndarray) -> sp.csr_matrix:
        """K from element matrices (d,d,e,a,b) in any memory layout (read in memory order)."""
        order = tuple(np.argsort([-s for s in element_matrices.strides], kind="stable"))
        slot = self.slot if order == tuple(range(5)) else self._slot_in(order)
        values = np.transpose(element_matrices, order)
        data = np.bincount(slot, weights=values.ravel(), minlength=len(self.indices))
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))

    def _slot_in(self, order: tuple[int, ...]) -> np.ndarray:
        """``slot`` permuted to the block layout with axes ``order`` (computed once per layout)."""
        cache = self.__dict__.setdefault("_slots", {})
        if order not in cache:
            n_el, n_loc = self.element_shape
            d = int(round((self.slot.size / (n_el * n_loc * n_loc)) ** 0.5))  # 3, or 2 for a sheet
            blocks = self.slot.reshape(d, d, n_el, n_loc, n_loc)
            cache[order] = np.ascontiguousarray(np.transpose(blocks, order)).ravel()
        return cache[order]


@dataclass(frozen=True)
class Partition:
    """Free/prescribed split of the DOFs with precomputed slices of the CSR data array.

    ``ff`` and ``fp`` are the data indices of K_ff and K_fp inside the full CSR data, so that
    extracting the blocks each iteration is a gather, not a sparse slicing operation.
    """

    free: np.ndarray
    prescribed: np.ndarray
    ff: np.ndarray
    ff_indptr: np.ndarray
    ff_indices: np.ndarray
    fp: np.ndarray
    fp_indptr: np.ndarray
    fp_indices: np.ndarray

    @classmethod
    def build(cls, pattern: SparsityPattern, prescribed: np.ndarray) -> "Partition":
        is_free = np.ones(pattern.n, dtype=bool)
        is_free[prescribed] = False
        free = np.flatnonzero(is_free)
        renumber = np.full(pattern.n, -1, dtype=np.int64)
        renumber[free] = np.arange(len(free))
        renumber_p = np.full(pattern.n, -1, dtype=np.int64)
        renumber_p[prescribed] = np.arange(len(prescribed))
        row = np.repeat(np.arange(pattern.n), np.diff(pattern.indptr))
        col = pattern.indices
        blocks = []
        for col_ok, col_map in ((is_free[col], renumber), (~is_free[col], renumber_p)):
            keep = np.flatnonzero(is_free[row] & col_ok)
            indptr = np.zeros(len(free) + 1, dtype=np.int64)
            np.cumsum(np.bincount(renumber[row[keep]], minlength=len(free)), out=indptr[1:])
            blocks += [keep, indptr, col_map[col[keep]].astype(np.int32)]
        return cls(free, np.asarray(prescribed), *blocks)

    def blocks(self, K: sp.csr_matrix) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """K_ff (free × free) and K_fp (free × prescribed) of an assembled K."""
        nf, npres = len(self.free), len(self.prescribed)
        Kff = sp.csr_matrix((K.data[self.ff], self.ff_indices, self.ff_indptr), shape=(nf, nf))
        Kfp = sp.csr_matrix((K.data[self.fp], self.fp_indices, self.fp_indptr), shape=(nf, npres))
        return Kff, Kfp


def element_forces(space: DisplacementSpace, P: np.ndarray) -> np.ndarray:
    """Σ_q P_iJ dN_a,J dx per element, shape (n_elements, n_local, d), N. P is (d,d,e,q)."""
    return np.einsum("iJeq,eqaJ,eq->eai", P, space.dN, space.dx, optimize=True)


def element_stiffness(space: DisplacementSpace, A: np.ndarray) -> np.ndarray:
    """K^e_{ai,bk} = Σ_q dN_a,J A_iJkL dN_b,L dx in block layout (i, k, e, a, b), N/mm.

    A is the material tangent (3,3,3,3,e,q). With a reference map (isoparametric elements) the
    tangent is pulled back to the reference cell,
        Â_imkn = dx Σ_JL ∂ξ_m/∂X_J A_iJkL ∂ξ_n/∂X_L,
    where the gradients dN̂ are shared by every element, so
        K^e_{ik}[a,b] = Σ_(q,m,n) Â_ik[e,(q,m,n)] · dN̂_qam dN̂_qbn
    is one dense matrix product (elements × 9 n_qp) @ (9 n_qp × n_local²) per (i, k): BLAS
    speed instead of millions of 3×3 products. Otherwise the generic contraction is used.

    A may also be a ``TangentTerms`` (vlab.materials.structure): then Â is formed term by term
    from a few 3×3 fields per point and the full A is never built.
    """
    if space.reference_dN is None:
        return _element_stiffness_generic(space, A if isinstance(A, np.ndarray) else A.full())
    if not isinstance(A, np.ndarray):
        R = np.ascontiguousarray(np.swapaxes(space.inverse_jacobian, 2, 3))  # (m, J, q, e)
        return _reference_gemm_batch_last(space, A.pulled_back(R, np.ascontiguousarray(space.dx.T)))
    R = space.inverse_jacobian                     # (m, J, e, q)
    Rw = R * space.dx                              # dx folded into the first pull-back
    X = np.empty_like(A)                           # X_imkL = Σ_J Rw_mJ A_iJkL
    for m in range(3):
        np.multiply(A[:, 0], Rw[m, 0], out=X[:, m])
        X[:, m] += A[:, 1] * Rw[m, 1]
        X[:, m] += A[:, 2] * Rw[m, 2]
    Z = np.empty_like(A)                           # Â_imkn = Σ_L X_imkL R_nL
    for n in range(3):
        np.multiply(X[:, :, :, 0], R[n, 0], out=Z[:, :, :, n])
        Z[:, :, :, n] += X[:, :, :, 1] * R[n, 1]
        Z[:, :, :, n] += X[:, :, :, 2] * R[n, 2]
    return _reference_gemm(space, np.ascontiguousarray(Z.transpose(0, 2, 4, 5, 1, 3)))


def _reference_gemm(space: DisplacementSpace, Y: np.ndarray) -> np.ndarray:
    """K^e_{ik}[a,b] = Σ_(q,m,n) Y[i,k,e,q,m,n] dN̂_qam dN̂_qbn as one GEMM per (i, k)."""
    n_el, n_qp, n_loc, _ = space.dN.shape
    G = space.reference_dN                         # (q, a, m)
    M = np.einsum("qam,qbn->qmnab", G, G).reshape(9 * n_qp, n_loc * n_loc)
    with single_threaded_blas():
        Ke = Y.reshape(9, n_el, 9 * n_qp) @ M
    return Ke.reshape(3, 3, n_el, n_loc, n_loc)


def _reference_gemm_batch_last(space: DisplacementSpace, Y: np.ndarray) -> np.ndarray:
    """As ``_reference_gemm`` with Y in the layout (i, k, q, m, n, e): (K^e_ik)ᵀ = Mᵀ Y_ik.

    Returns a (3,3,e,a,b) view of a contiguous (i, k, a, b, e) array (SparsityPattern.matrix
    reads it in memory order, no copy)."""
    n_el, n_qp, n_loc, _ = space.dN.shape
    G = space.reference_dN                         # (q, a, m)
    MT = np.einsum("qam,qbn->abqmn", G, G).reshape(n_loc * n_loc, 9 * n_qp)
    with single_threaded_blas():
        Ke = np.matmul(MT, Y.reshape(9, 9 * n_qp, n_el))
    return Ke.reshape(3, 3, n_loc, n_loc, n_el).transpose(0, 1, 4, 2, 3)


_BLAS: list = []


def single_threaded_blas():
    """Context limiting numpy's BLAS to one thread (threadpoolctl, if installed).

    The element GEMMs are short; BLAS worker threads that keep spinning after them steal the
    cores from the sparse factorization that follows (2× slower iterations measured on 2 cores).
    """
    if not _BLAS:
        try:
            from threadpoolctl import ThreadpoolController
            _BLAS.append(ThreadpoolController())
        except ImportError:
            _BLAS.append(None)
    if _BLAS[0] is None:
        return contextlib.nullcontext()
    return _BLAS[0].limit(limits=1, user_api="blas")


def _element_stiffness_generic(space: DisplacementSpace, A: np.ndarray) -> np.ndarray:
    """Same result as ``element_stiffness`` from the physical gradients dN (any element, and
    any dimension d = 3 or 2 of the tangent A (d,d,d,d,e,q)).

    T = A·dN_b over L per quadrature point, then one product over (q, J) per element."""
    dN, dx = space.dN, space.dx
    n_el, n_qp, n_loc, d = dN.shape
    Aw = np.moveaxis(A, (4, 5), (0, 1)) * dx[:, :, None, None, None, None]  # (e,q,i,J,k,L)
    T = Aw.reshape(n_el, n_qp, d**3, d) @ dN.transpose(0, 1, 3, 2)  # (e,q,(i,J,k),b)
    T = T.reshape(n_el, n_qp, d, d, d * n_loc).transpose(0, 1, 3, 2, 4)  # (e,q,J,i,(k,b))
    T = T.reshape(n_el, d * n_qp, d * d * n_loc)
    G = dN.transpose(0, 2, 1, 3).reshape(n_el, n_loc, d * n_qp)  # (e,a,(q,J))
    Ke = (G @ T).reshape(n_el, n_loc, d, d, n_loc)  # (e,a,i,k,b)
    return np.ascontiguousarray(Ke.transpose(2, 3, 0, 1, 4))


def scatter_vector(space: DisplacementSpace, fe: np.ndarray) -> np.ndarray:
    """Sum element vectors (n_elements, n_local, dim) into a global vector of length n_dofs."""
    return np.bincount(space.element_dofs.ravel(), weights=fe.ravel(), minlength=space.n_dofs)
