"""Vectorized assembly of the total energy, internal force and tangent stiffness.

The tangents of the linear, StVK and Neo-Hookean models are assembled by the compiled kernel of
vlab.fe.compiled when numba is installed; the numpy kernels here do every other case (2D
sheets, other tangent forms, ``VLAB_KERNEL=numpy``) and are the reference it is tested against.
Material and mesh meet here and in vlab.fe.compiled, nowhere else. Per Newton iteration F, P
and A are evaluated once at all quadrature points; element contributions are formed with
batched tensor contractions and scattered into a sparsity pattern that is computed once per
mesh (and once per set of grips).

    W(u)      = Σ_e Σ_q ψ(F_eq) dx_eq                                     (mJ = N·mm)
    f_int[ai] = Σ_e Σ_q P_iJ dN_a,J dx                                     (N)
    K[ai,bk]  = Σ_e Σ_q dN_a,J A_iJkL dN_b,L dx                             (N/mm)
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from vlab.fe.blas import single_threaded_blas
from vlab.fe.space import DisplacementSpace
from vlab.materials.structure import UPPER_PAIRS


@dataclass(frozen=True)
class SparsityPattern:
    """CSR pattern of the global stiffness and the map from element entries to CSR slots.

    Built from the node-pair pattern (d² times smaller than the DOF pattern): the DOF row
    d·A + i holds, for every node B coupled to node A (sorted) and every component k, the column
    d·B + k, so the CSR data index of the entry (A, i, B, k) is

        base[s] + i · rowlen[s] + k,   base[s] = d² indptr_A + d (s − indptr_A),  rowlen = d n_A,

    with s the node-pair slot of (A, B) and n_A the nodes coupled to A. Element matrices come in
    the block layout (i, k, e, a, b) of ``element_stiffness`` (``slot`` maps every entry to its
    CSR index, so assembly is one weighted ``bincount``) or, for a symmetric K, as the six blocks
    i ≤ k of ``upper_element_stiffness`` (``symmetric_matrix``).
    """

    n: int
    indptr: np.ndarray
    indices: np.ndarray
    node_slot: np.ndarray   # (n_elements, n_local, n_local) node-pair slot of (node[e,a], node[e,b])
    base: np.ndarray        # (node pairs,) CSR index of the pair's entry (i, k) = (0, 0)
    rowlen: np.ndarray      # (node pairs,) length of a DOF row of the pair's first node
    transpose: np.ndarray   # (node pairs,) slot of the pair (B, A)
    dim: int = 3

    @classmethod
    def build(cls, element_nodes: np.ndarray, dim: int = 3) -> "SparsityPattern":
        d = dim
        nodes = np.asarray(element_nodes, dtype=np.int64)
        n_nodes = int(nodes.max()) + 1
        keys, node_slot = np.unique((nodes[:, :, None] * n_nodes + nodes[:, None, :]).ravel(),
                                    return_inverse=True)
        row, col = keys // n_nodes, keys % n_nodes
        counts = np.bincount(row, minlength=n_nodes)
        start = np.zeros(n_nodes + 1, dtype=np.int64)
        np.cumsum(counts, out=start[1:])
        base = d * d * start[row] + d * (np.arange(len(keys)) - start[row])
        rowlen = d * counts[row]
        indptr = np.zeros(d * n_nodes + 1, dtype=np.int64)
        np.cumsum(np.repeat(d * counts, d), out=indptr[1:])
        comp = np.arange(d)
        where = base[:, None, None] + comp[None, :, None] * rowlen[:, None, None] + comp[None, None, :]
        indices = np.empty(indptr[-1], dtype=np.int32)
        indices[where.ravel()] = np.broadcast_to(d * col[:, None, None] + comp[None, None, :],
                                                 where.shape).ravel()
        indptr = _compact(indptr)
        transpose = np.searchsorted(keys, col * n_nodes + row)
        return cls(d * n_nodes, indptr, indices, node_slot.reshape(nodes.shape + nodes.shape[1:2]),
                   base, rowlen, transpose, d)

    @property
    def element_shape(self) -> tuple[int, int]:
        return self.node_slot.shape[:2]

    def entry(self, pair, i, k) -> np.ndarray:
        """CSR data index of the entry (row component i, column component k) of node pair(s)."""
        return self.base[pair] + i * self.rowlen[pair] + k

    @cached_property
    def slot(self) -> np.ndarray:
        """(d² · n_elements · n_local²,) CSR data index of every entry (i, k, e, a, b)."""
        comp = np.arange(self.dim)
        return self.entry(self.node_slot[None, None], comp[:, None, None, None, None],
                          comp[None, :, None, None, None]).ravel()

    def matrix(self, element_matrices: np.ndarray) -> sp.csr_matrix:
        """K from element matrices (d,d,e,a,b) in any memory layout (read in memory order)."""
        order = tuple(np.argsort([-s for s in element_matrices.strides], kind="stable"))
        slot = self.slot if order == tuple(range(5)) else self._slot_in(order)
        values = np.transpose(element_matrices, order)
        return self.csr(np.bincount(slot, weights=values.ravel(), minlength=len(self.indices)))

    def symmetric_matrix(self, blocks: np.ndarray) -> sp.csr_matrix:
        """K from the flat element blocks of ``upper_element_stiffness``: the diagonal blocks
        i = k as their entries a ≤ b, then the blocks i < k whole.

        Every diagonal-block entry goes to the upper-triangle entry of its node pair; the blocks
        i < k go where they belong. The rest (i > k, and i = k below the diagonal) is then copied
        from its transpose, K_(Ai)(Bk) = K_(Bk)(Ai): a gather of about half the nonzeros."""
        data = np.bincount(self._split_slots, weights=blocks, minlength=len(self.indices))
        lower, source = self._mirror
        data[lower] = data[source]
        return self.csr(data)

    def csr(self, data: np.ndarray) -> sp.csr_matrix:
        """The matrix with these CSR data values (n × n), sharing the pattern's index arrays."""
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))

    @cached_property
    def _split_slots(self) -> np.ndarray:
        """CSR indices of the entries (p, (a ≤ b), e) of the diagonal blocks, each sent to the
        upper-triangle entry of its node pair, then of (p, a, b, e) of the blocks i < k."""
        n_loc = self.node_slot.shape[1]
        a, b = np.triu_indices(n_loc)
        s = np.ascontiguousarray(self.node_slot.transpose(1, 2, 0))     # (a, b, e)
        pair = s[a, b]                                                   # (pairs, e)
        upper = np.where(self._is_upper_pair[pair], pair, self.transpose[pair])
        return np.concatenate([self.entry(upper if i == k else s, i, k).ravel()
                               for i, k in UPPER_PAIRS])         # diagonal blocks come first

    @cached_property
    def _is_upper_pair(self) -> np.ndarray:
        """(node pairs,) True where the pair (A, B) has A ≤ B."""
        return np.arange(len(self.base)) <= self.transpose

    @cached_property
    def _mirror(self) -> tuple[np.ndarray, np.ndarray]:
        """(CSR index of every entry filled from its transpose, CSR index of that transpose):
        all entries with i > k, and those with i = k of node pairs A > B."""
        every, t = np.arange(len(self.base)), self.transpose
        below = np.flatnonzero(~self._is_upper_pair)
        pairs = ([(every, i, k) for i in range(self.dim) for k in range(i)]
                 + [(below, i, i) for i in range(self.dim)])
        return (np.concatenate([self.entry(p, i, k) for p, i, k in pairs]),
                np.concatenate([self.entry(t[p], k, i) for p, i, k in pairs]))

    def _slot_in(self, order: tuple[int, ...]) -> np.ndarray:
        """``slot`` permuted to the block layout with axes ``order`` (computed once per layout)."""
        cache = self.__dict__.setdefault("_slots", {})
        if order not in cache:
            n_el, n_loc = self.element_shape
            blocks = self.slot.reshape(self.dim, self.dim, n_el, n_loc, n_loc)
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
    pp: np.ndarray  # the prescribed × prescribed block likewise (the path slope's û_pᵀ K_pp û_p)
    pp_indptr: np.ndarray
    pp_indices: np.ndarray

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
        for rows_ok, row_map, n_rows, col_ok, col_map in (
                (is_free[row], renumber, len(free), is_free[col], renumber),
                (is_free[row], renumber, len(free), ~is_free[col], renumber_p),
                (~is_free[row], renumber_p, len(prescribed), ~is_free[col], renumber_p)):
            keep = np.flatnonzero(rows_ok & col_ok)
            indptr = np.zeros(n_rows + 1, dtype=np.int64)
            np.cumsum(np.bincount(row_map[row[keep]], minlength=n_rows), out=indptr[1:])
            # the data positions as int32 when they fit (nnz < 2³¹): half the memory of the
            # largest index arrays a run keeps (0.6 kB per free DOF of a Q1 hex mesh in int64)
            positions = keep.astype(np.int32) if pattern.indptr[-1] < np.iinfo(np.int32).max else keep
            blocks += [positions, _compact(indptr), col_map[col[keep]].astype(np.int32)]
        return cls(free, np.asarray(prescribed), *blocks)

    def blocks(self, K: sp.csr_matrix) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """K_ff (free × free) and K_fp (free × prescribed) of an assembled K."""
        nf, npres = len(self.free), len(self.prescribed)
        Kff = sp.csr_matrix((K.data[self.ff], self.ff_indices, self.ff_indptr), shape=(nf, nf))
        Kfp = sp.csr_matrix((K.data[self.fp], self.fp_indices, self.fp_indptr), shape=(nf, npres))
        return Kff, Kfp

    def prescribed_block(self, K: sp.csr_matrix) -> sp.csr_matrix:
        """K_pp (prescribed × prescribed) of an assembled K."""
        n = len(self.prescribed)
        return sp.csr_matrix((K.data[self.pp], self.pp_indices, self.pp_indptr), shape=(n, n))


def _compact(indptr: np.ndarray) -> np.ndarray:
    """indptr as int32 when it fits, like the indices: scipy then takes both arrays as they are
    (an int64 indptr makes every CSR construction check its range, 0.1–0.3 ms each)."""
    return indptr.astype(np.int32) if indptr[-1] < np.iinfo(np.int32).max else indptr


def element_forces(space: DisplacementSpace, P: np.ndarray) -> np.ndarray:
    """Σ_q P_iJ dN_a,J dx per element, shape (n_elements, n_local, d), N. P is (d,d,e,q)."""
    return space.element_forces(P)


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
        return _blocks_from_upper(space, A)
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


def _blocks_from_upper(space: DisplacementSpace, terms) -> np.ndarray:
    """The full block layout (i, k, e, a, b) of a TangentTerms' stiffness from its upper blocks
    (upper_element_stiffness): K_ik = K_kiᵀ by the major symmetry, each diagonal block symmetric."""
    n_loc = space.dN.shape[2]
    diagonal, off = split_upper(upper_element_stiffness(space, terms), n_loc, space.dN.shape[0])
    a, b = np.triu_indices(n_loc)
    Ke = np.empty((3, 3) + off.shape[1:])
    for p, (i, k) in enumerate(UPPER_PAIRS):
        if i == k:
            Ke[i, i][a, b] = diagonal[p]
            Ke[i, i][b, a] = diagonal[p]
        else:
            Ke[i, k] = off[p - 3]
            Ke[k, i] = off[p - 3].transpose(1, 0, 2)
    return Ke.transpose(0, 1, 4, 2, 3)


def _reference_gemm(space: DisplacementSpace, Y: np.ndarray) -> np.ndarray:
    """K^e_{ik}[a,b] = Σ_(q,m,n) Y[i,k,e,q,m,n] dN̂_qam dN̂_qbn as one GEMM per (i, k)."""
    n_el, n_qp, n_loc, _ = space.dN.shape
    G = space.reference_dN                         # (q, a, m)
    M = np.einsum("qam,qbn->qmnab", G, G).reshape(9 * n_qp, n_loc * n_loc)
    with single_threaded_blas():
        Ke = Y.reshape(9, n_el, 9 * n_qp) @ M
    return Ke.reshape(3, 3, n_el, n_loc, n_loc)


def upper_element_stiffness(space: DisplacementSpace, terms) -> np.ndarray:
    """The element blocks i ≤ k of K^e, N/mm, flat in a workspace array of the space (valid
    until the next call): the diagonal blocks (0,0), (1,1), (2,2) as their entries a ≤ b,
    (3, n_local(n_local+1)/2, n_elements), then the blocks (0,1), (0,2), (1,2) whole,
    (3, n_local, n_local, n_elements); ``split_upper`` gives the two views.

    For a tangent given as ``TangentTerms`` on an isoparametric 3D space: Â (6, q, m, n, e) from
    ``TangentTerms.pulled_back``, then K^e_ik[(a,b), e] = Σ_(q,m,n) dN̂_qam dN̂_qbn Â_ik[(q,m,n), e]
    is one dense product (n_local² × 9 n_qp) @ (9 n_qp × n_elements) per block. The blocks i > k
    are the transposes (major symmetry) and a diagonal block is symmetric in (a, b), so 6
    products instead of 9, the diagonal ones with the rows a ≤ b only."""
    n_el, n_qp, n_loc, _ = space.dN.shape
    n = len(UPPER_PAIRS)
    Y = terms.pulled_back(space.inverse_jacobian_qe, space.dx_qe,
                          out=space.workspace("pulled-back tangent", (n, n_qp, 3, 3, n_el)))
    Y = Y.reshape(n, 9 * n_qp, n_el)
    pairs = n_loc * (n_loc + 1) // 2
    flat = space.workspace("upper element blocks", (3 * (pairs + n_loc * n_loc) * n_el,))
    diagonal, off = split_upper(flat, n_loc, n_el)
    with single_threaded_blas():
        np.matmul(space.reference_products_upper, Y[:3], out=diagonal)
        np.matmul(space.reference_products, Y[3:], out=off.reshape(3, n_loc * n_loc, n_el))
    return flat


def split_upper(flat: np.ndarray, n_loc: int, n_el: int) -> tuple[np.ndarray, np.ndarray]:
    """Views (diagonal (3, n_local(n_local+1)/2, e), off (3, n_local, n_local, e)) of the flat
    blocks of ``upper_element_stiffness``."""
    size = 3 * n_loc * (n_loc + 1) // 2 * n_el
    return (flat[:size].reshape(3, -1, n_el), flat[size:].reshape(3, n_loc, n_loc, n_el))


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
