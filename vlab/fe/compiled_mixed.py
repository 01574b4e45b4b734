"""Compiled tangent of the mixed (condensed three-field) body: element matrices built and added
into the CSR data in one pass, as vlab.fe.compiled does for the displacement tangent.

The condensed tangent of vlab.fe.mixed, per element (N/mm),

    K[ai,bk] = Σ_q dx g_aJ (A_iso + p ∂²v/∂F∂F)_iJkL g_bL  +  Σ_mn G[m,ai] C[m,n] G[n,bk],
    G[m,ai]  = Σ_q φ_m(q) (∂v/∂F)_iJ g_aJ dx_q,      C = M⁻¹ H M⁻¹,   H = Σ_q U''(θ_q) φ φᵀ dx_q,

with g_aJ = ∂N_a/∂X_J = Σ_m ∂N̂_a/∂ξ_m R_mJ (R = ∂ξ/∂X, 9 numbers a point, as in
vlab.fe.compiled), A_iso the law's isochoric tangent (3,3,3,3,e,q) and ∂²v/∂F∂F its volume
Hessian (MPa; evaluated by the law in numpy, any split law), p the projected pressure (MPa) and
C (e, m, m) = M⁻¹ H M⁻¹ the condensed volumetric stiffness of the θ space (MPa/mm³ for
P0). The kernel never forms the (3,3,3,3,e,q) sum A_iso + p ∂²v, nor the element matrices: per
point it contracts g with A (w_a,ikL = dx Σ_J g_aJ A_iJkL, then Σ_L w_a,ikL g_bL), adds the
volumetric rank-m update after the element's points, and scatters every 3 × 3 node block into the
CSR data. K is symmetric (A has the major symmetry of a second derivative, C is symmetric), so
only the node blocks b ≥ a are computed and each is also added, transposed, as the block (b, a)
(entry (A, i, B, k) at ``base + i·rowlen + k``, see vlab.fe.assembly.SparsityPattern).

The source is fixed (the loops run over n_local and the θ-space size m at run time: one kernel
for Q1/P0, Q2/P1dc and P2/P0); it is written once to vlab's kernel cache and imported from there
(vlab.jit.load), so numba's on-disk cache of the machine code serves later processes. Threads:
the element slabs of vlab.fe.compiled (two phases of slabs that share no node). The numpy
assembly of vlab.fe.mixed stays the reference (compared entry by entry in tests/test_mixed_compiled.py).
"""

from __future__ import annotations

import threading
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from vlab import jit

SOURCE = '''
import numpy as np
import numba


@numba.njit(cache=True, fastmath=True, boundscheck=False, nogil=True, parallel=True)
def slabs(dN, R, dx, A, H, p, V, phi, C, base, rowlen, bounds, data):
    """The elements of slabs bounds[s]:bounds[s + 1], the two parities one after the other
    (slabs of one parity share no node: no two threads add into one entry)."""
    n_slabs = bounds.shape[0] - 1
    for parity in range(2):
        for c in numba.prange((n_slabs + 1 - parity) // 2):
            s = 2 * c + parity
            stiffness(dN, R, dx, A, H, p, V, phi, C, base, rowlen, bounds[s], bounds[s + 1], data)


@numba.njit(cache=True, fastmath=True, boundscheck=False, nogil=True)
def stiffness(dN, R, dx, A, H, p, V, phi, C, base, rowlen, start, stop, data):
    """Elements start ... stop - 1 of the condensed mixed tangent (vlab.fe.compiled_mixed)."""
    n_qp = dN.shape[0]
    n_loc = dN.shape[2]
    n_m = phi.shape[2]
    with_H = H.shape[0] == 3
    g = np.empty((n_loc, 3))
    t = np.empty((3, 3, 3, 3))
    w = np.empty((n_loc, 3, 3, 3))
    K = np.empty((n_loc, 3, n_loc, 3))
    G = np.empty((n_m, n_loc, 3))
    for e in range(start, stop):
        K[:] = 0.0
        G[:] = 0.0
        for q in range(n_qp):
            dxq = dx[e, q]
            for a in range(n_loc):
                for J in range(3):
                    g[a, J] = (dN[q, 0, a] * R[e, q, 0, J] + dN[q, 1, a] * R[e, q, 1, J]
                               + dN[q, 2, a] * R[e, q, 2, J])
            pq = p[e, q]
            for i in range(3):
                for J in range(3):
                    for k in range(3):
                        for L in range(3):
                            x = A[i, J, k, L, e, q]
                            if with_H:
                                x += pq * H[i, J, k, L, e, q]
                            t[i, J, k, L] = x * dxq
            for a in range(n_loc):
                g0, g1, g2 = g[a, 0], g[a, 1], g[a, 2]
                for i in range(3):
                    for k in range(3):
                        for L in range(3):
                            w[a, i, k, L] = g0 * t[i, 0, k, L] + g1 * t[i, 1, k, L] + g2 * t[i, 2, k, L]
            for a in range(n_loc):
                for i in range(3):
                    for b in range(a, n_loc):  # the blocks b >= a; K is symmetric
                        h0, h1, h2 = g[b, 0], g[b, 1], g[b, 2]
                        for k in range(3):
                            K[a, i, b, k] += w[a, i, k, 0] * h0 + w[a, i, k, 1] * h1 + w[a, i, k, 2] * h2
            for m in range(n_m):
                c = phi[e, q, m] * dxq
                for a in range(n_loc):
                    for i in range(3):
                        G[m, a, i] += c * (V[i, 0, e, q] * g[a, 0] + V[i, 1, e, q] * g[a, 1]
                                           + V[i, 2, e, q] * g[a, 2])
        for m in range(n_m):
            for n in range(n_m):
                cmn = C[e, m, n]
                for a in range(n_loc):
                    for i in range(3):
                        x = cmn * G[m, a, i]
                        for b in range(a, n_loc):
                            for k in range(3):
                                K[a, i, b, k] += x * G[n, b, k]
        for a in range(n_loc):
            r = rowlen[e, a]
            for b in range(a, n_loc):
                s0 = base[e, a, b]
                for i in range(3):
                    for k in range(3):
                        data[s0 + i * r + k] += K[a, i, b, k]
                if b > a:  # the block (b, a) is the transpose of (a, b)
                    s1, rb = base[e, b, a], rowlen[e, b]
                    for i in range(3):
                        for k in range(3):
                            data[s1 + k * rb + i] += K[a, i, b, k]
'''

_MODULE: list = []
_NONE = np.empty((0, 0, 0, 0, 0, 0))


def _kernels():
    if not _MODULE:
        _MODULE.append(jit.load("mixed_stiffness", SOURCE))
    return _MODULE[0]


class CompiledMixedTangent:
    """The compiled condensed tangent on one mesh; ``fast`` is the mesh's
    vlab.fe.compiled.CompiledKernels (reference gradients, R, CSR slots, slabs)."""

    def __init__(self, fast, projection):
        self.fast, self.projection = fast, projection

    @cached_property
    def phi(self) -> np.ndarray:
        return np.ascontiguousarray(self.projection.phi)

    def prepare(self) -> None:
        """Compile the kernel or load it from numba's cache (a call on no elements)."""
        n_qp = self.fast.space.dx.shape[1]
        for bounds in ([0, 0], [0, 0, 0]):  # the serial kernel, then the threaded one
            self._run(np.zeros((3, 3, 3, 3, 0, n_qp)), _NONE, np.zeros((0, n_qp)), np.zeros((3, 3, 0, n_qp)),
                      np.zeros((0, 1, 1)), np.zeros(len(self.fast.pattern.indices)),
                      np.array(bounds, dtype=np.int64))

    def matrix(self, A: np.ndarray, hessian: np.ndarray | None, pressure: np.ndarray, V: np.ndarray,
               C: np.ndarray) -> sp.csr_matrix:
        """K (N/mm) from A_iso (3,3,3,3,e,q), the volume Hessian (or None), p (e,q),
        ∂v/∂F (3,3,e,q) and C = M⁻¹ H M⁻¹ (e,m,m)."""
        data = np.zeros(len(self.fast.pattern.indices))
        self._run(np.ascontiguousarray(A), _NONE if hessian is None else np.ascontiguousarray(hessian),
                  np.ascontiguousarray(pressure, dtype=float), np.ascontiguousarray(V),
                  np.ascontiguousarray(C), data, self.fast.bounds)
        return self.fast.pattern.csr(data)

    def _run(self, A, H, p, V, C, data, bounds) -> None:
        fast = self.fast
        base, rowlen = fast.slots
        phi = self.phi if C.shape[0] else np.zeros((0, 1, 1))
        args = (fast.reference_gradients, fast.inverse_jacobians, fast.space.dx, A, H, p, V, phi, C,
                base, rowlen)
        k = _kernels()
        # numba's workqueue layer must not be entered from two threads at once (vlab.fe.compiled)
        if len(bounds) > 2 and threading.current_thread() is threading.main_thread():
            jit.call(k.slabs, *args, np.asarray(bounds, dtype=np.int64), data)
        else:
            jit.call(k.stiffness, *args, int(bounds[0]), int(bounds[-1]), data)
