"""Closed-form eigensystem of symmetric 3×3 matrices, batched and compiled (vlab.jit).

Scherzinger & Dohrmann (2008, Comput. Methods Appl. Mech. Engrg. 197, 4007–4015), per matrix A
(scaled by its largest entry s, so nothing over- or underflows):

    m = tr A / 3,   D = A − m I,   J2 = ½ D:D,   J3 = det D
    cos 3α = (J3/2) (3/J2)^(3/2)                  (clamped to [−1, 1]; α ∈ [0, π/3])
    η₁ = 2 √(J2/3) cos α            if α < π/6   (the largest deviatoric eigenvalue)
    η₁ = 2 √(J2/3) cos(α + 2π/3)    otherwise    (the smallest)

η₁ is always the eigenvalue *most distinct* from the other two, so it is simple whenever J2 > 0,
and where two eigenvalues coalesce (α → 0 or π/3) the cosine is stationary in α: acos's
√ε error in α costs only O(ε) in η₁ (Smith's 1961 formula evaluated for all three roots loses
half the digits there). Its eigenvector is the normal of the range of D − η₁ I: with r_k that
matrix's longest row, s₁ = r_k/|r_k|, t the longer of the other rows minus their s₁ part,
s₂ = t/|t|, v₁ = s₁ × s₂. The remaining pair comes from the 2×2 problem of D on span{s₁, s₂}:

    η₂,₃ = ½ (d₁₁ + d₂₂) ± ½ √((d₁₁ − d₂₂)² + 4 d₁₂²),   v₂ ⟂ the longer row of (d − η₂ I), v₃ = v₁ × v₂

which is exact for equal η₂ = η₃ (the rows vanish: any unit v₂ in the plane is an eigenvector).
J2 = 0 (A = m I) returns V = I. The eigenvectors are orthonormal by construction; eigenvalues
λ = m + η are returned ascending (numpy.linalg.eigh's order), each column V[:, k] its vector.
Accuracy (tests/test_principal_eig.py): eigenvalues within ~1e−15 ‖A‖ of LAPACK's, ‖V Λ Vᵀ − A‖
at round-off, also at repeated and nearly repeated (1e−8) spectra.

The numpy twin (VLAB_KERNEL=numpy, numba missing, or batches below ``_COMPILED_FROM``) is
``numpy.linalg.eigh``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["eigh3", "compiled_kernels"]

_COMPILED_FROM = 64  # matrices: below, numpy's eigh is as fast as the kernel's call overhead

SOURCE = '''
import math

import numba

_OPTIONS = dict(cache=True, boundscheck=False, nogil=True, error_model="numpy")


@numba.njit(inline="always", **_OPTIONS)
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@numba.njit(inline="always", **_OPTIONS)
def _distinct(d0, d1, d2, a01, a02, a12, J2):
    """η₁, the deviatoric eigenvalue most distinct from the other two (module docstring)."""
    J3 = d0 * (d1 * d2 - a12 * a12) - a01 * (a01 * d2 - a12 * a02) + a02 * (a01 * a12 - d1 * a02)
    c3 = min(1.0, max(-1.0, 0.5 * J3 * (3.0 / J2) ** 1.5))
    alpha = math.acos(c3) / 3.0
    rad = 2.0 * math.sqrt(J2 / 3.0)
    if alpha < math.pi / 6.0:
        return rad * math.cos(alpha)
    return rad * math.cos(alpha + 2.0 * math.pi / 3.0)


@numba.njit(inline="always", **_OPTIONS)
def _range_basis(r0, r1, r2):
    """(s₁, s₂): an orthonormal basis of the span of the rows of D − η₁ I (rank 2)."""
    n0, n1, n2 = _dot(r0, r0), _dot(r1, r1), _dot(r2, r2)
    if n0 >= n1 and n0 >= n2:
        p, q1, q2, npp = r0, r1, r2, n0
    elif n1 >= n2:
        p, q1, q2, npp = r1, r0, r2, n1
    else:
        p, q1, q2, npp = r2, r0, r1, n2
    s1 = _scale(p, 1.0 / math.sqrt(npp))
    t1 = _minus(q1, _scale(s1, _dot(s1, q1)))
    t2 = _minus(q2, _scale(s1, _dot(s1, q2)))
    m1, m2 = _dot(t1, t1), _dot(t2, t2)
    if m1 >= m2:
        return s1, _scale(t1, 1.0 / math.sqrt(m1))
    return s1, _scale(t2, 1.0 / math.sqrt(m2))


@numba.njit(inline="always", **_OPTIONS)
def _pair2x2(b11, b12, b22):
    """(η₂ ≥ η₃, (x0, x1)): eigenvalues of [[b11, b12], [b12, b22]] and the unit vector of η₂."""
    half, mid = 0.5 * (b11 - b22), 0.5 * (b11 + b22)
    root = math.sqrt(half * half + b12 * b12)
    e2, e3 = mid + root, mid - root
    p0, p1, q0, q1 = b11 - e2, b12, b12, b22 - e2   # rows of (b − η₂ I); the vector ⟂ the longer
    if p0 * p0 + p1 * p1 >= q0 * q0 + q1 * q1:
        x0, x1 = -p1, p0
    else:
        x0, x1 = -q1, q0
    nx = math.sqrt(x0 * x0 + x1 * x1)
    if nx == 0.0:   # η₂ = η₃: any unit vector of the plane
        return e2, e3, 1.0, 0.0
    return e2, e3, x0 / nx, x1 / nx


@numba.njit(inline="always", **_OPTIONS)
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(inline="always", **_OPTIONS)
def _scale(a, c):
    return (a[0] * c, a[1] * c, a[2] * c)


@numba.njit(inline="always", **_OPTIONS)
def _minus(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@numba.njit(inline="always", **_OPTIONS)
def _apply(d0, d1, d2, a01, a02, a12, v):
    """D v for the symmetric D with diagonal (d0, d1, d2) and off-diagonals a01, a02, a12."""
    return (d0 * v[0] + a01 * v[1] + a02 * v[2], a01 * v[0] + d1 * v[1] + a12 * v[2],
            a02 * v[0] + a12 * v[1] + d2 * v[2])


@numba.njit(**_OPTIONS)
def eig3(a00, a01, a02, a11, a12, a22):
    """(w0, w1, w2, V as 9 entries row-major) of a symmetric 3×3 matrix, w ascending."""
    s = max(abs(a00), abs(a01), abs(a02), abs(a11), abs(a12), abs(a22))
    if s == 0.0:
        return 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
    r = 1.0 / s
    a00, a01, a02, a11, a12, a22 = a00 * r, a01 * r, a02 * r, a11 * r, a12 * r, a22 * r
    m = (a00 + a11 + a22) / 3.0
    d0, d1, d2 = a00 - m, a11 - m, a22 - m
    J2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + a01 * a01 + a02 * a02 + a12 * a12
    if J2 < 1e-60:
        w = m * s
        return w, w, w, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
    e1 = _distinct(d0, d1, d2, a01, a02, a12, J2)
    s1, s2 = _range_basis((d0 - e1, a01, a02), (a01, d1 - e1, a12), (a02, a12, d2 - e1))
    v1 = _cross(s1[0], s1[1], s1[2], s2[0], s2[1], s2[2])
    y, z = _apply(d0, d1, d2, a01, a02, a12, s1), _apply(d0, d1, d2, a01, a02, a12, s2)
    e2, e3, x0, x1 = _pair2x2(_dot(s1, y), _dot(s2, y), _dot(s2, z))
    v2 = (x0 * s1[0] + x1 * s2[0], x0 * s1[1] + x1 * s2[1], x0 * s1[2] + x1 * s2[2])
    v3 = _cross(v1[0], v1[1], v1[2], v2[0], v2[1], v2[2])
    l1, l2, l3 = (m + e1) * s, (m + e2) * s, (m + e3) * s
    if e1 >= e2:   # ascending; e3 <= e2 always
        return (l3, l2, l1, v3[0], v2[0], v1[0], v3[1], v2[1], v1[1], v3[2], v2[2], v1[2])
    if e1 <= e3:
        return (l1, l3, l2, v1[0], v3[0], v2[0], v1[1], v3[1], v2[1], v1[2], v3[2], v2[2])
    return (l3, l1, l2, v3[0], v1[0], v2[0], v3[1], v1[1], v2[1], v3[2], v1[2], v2[2])


@numba.njit(**_OPTIONS)
def eigh_batch(A, w, V):
    """A (n,3,3) symmetric -> w (n,3) ascending, V (n,3,3) with V[p, :, k] the k-th vector."""
    for p in range(A.shape[0]):
        out = eig3(A[p, 0, 0], A[p, 0, 1], A[p, 0, 2], A[p, 1, 1], A[p, 1, 2], A[p, 2, 2])
        w[p, 0], w[p, 1], w[p, 2] = out[0], out[1], out[2]
        V[p, 0, 0], V[p, 0, 1], V[p, 0, 2] = out[3], out[4], out[5]
        V[p, 1, 0], V[p, 1, 1], V[p, 1, 2] = out[6], out[7], out[8]
        V[p, 2, 0], V[p, 2, 1], V[p, 2, 2] = out[9], out[10], out[11]


@numba.njit(inline="always", **_OPTIONS)
def frame_point(F, p, lam, N, n):
    """Point p of F (3,3,p): principal stretches lam[:, p], N[:, :, p] (eigenvectors of C = FᵀF)
    and n[:, :, p] = F N_A / λ_A (shared by frame_batch and the Ogden kernel)."""
    c00 = F[0, 0, p] * F[0, 0, p] + F[1, 0, p] * F[1, 0, p] + F[2, 0, p] * F[2, 0, p]
    c01 = F[0, 0, p] * F[0, 1, p] + F[1, 0, p] * F[1, 1, p] + F[2, 0, p] * F[2, 1, p]
    c02 = F[0, 0, p] * F[0, 2, p] + F[1, 0, p] * F[1, 2, p] + F[2, 0, p] * F[2, 2, p]
    c11 = F[0, 1, p] * F[0, 1, p] + F[1, 1, p] * F[1, 1, p] + F[2, 1, p] * F[2, 1, p]
    c12 = F[0, 1, p] * F[0, 2, p] + F[1, 1, p] * F[1, 2, p] + F[2, 1, p] * F[2, 2, p]
    c22 = F[0, 2, p] * F[0, 2, p] + F[1, 2, p] * F[1, 2, p] + F[2, 2, p] * F[2, 2, p]
    out = eig3(c00, c01, c02, c11, c12, c22)
    for A in range(3):
        l = math.sqrt(out[A])
        lam[A, p] = l
        N0, N1, N2 = out[3 + A], out[6 + A], out[9 + A]
        N[0, A, p], N[1, A, p], N[2, A, p] = N0, N1, N2
        r = 1.0 / l
        for i in range(3):
            n[i, A, p] = (F[i, 0, p] * N0 + F[i, 1, p] * N1 + F[i, 2, p] * N2) * r


@numba.njit(**_OPTIONS)
def frame_batch(F, lam, N, n):
    """F (3,3,p) -> principal stretches lam (3,p), N[J, A, p] (eigenvectors of C = FᵀF) and
    n[i, A, p] = F N_A / λ_A."""
    for p in range(F.shape[2]):
        frame_point(F, p, lam, N, n)
'''

_KERNELS: list = []


def compiled_kernels():
    """The compiled module (``eig3``, ``eigh_batch``, ``frame_batch``), or None without numba."""
    if not _KERNELS:
        from vlab import jit, settings  # numba starts on the first large batch, not with this module
        _KERNELS.append(jit.load("principal_eig", SOURCE) if jit.available(settings.current()) else None)
    return _KERNELS[0]


def eigh3(A: np.ndarray, compiled: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(w, V) of symmetric A (*batch, 3, 3) as ``numpy.linalg.eigh``: w ascending (*batch, 3),
    V[..., :, k] the unit eigenvector of w[..., k]. ``compiled``: None picks the kernel for
    batches of at least ``_COMPILED_FROM`` matrices when numba is available; True requires it."""
    A = np.asarray(A, dtype=float)
    batch = A.shape[:-2]
    size = int(np.prod(batch, dtype=int))
    kernels = compiled_kernels() if compiled is not False else None
    if compiled and kernels is None:
        raise RuntimeError("the compiled eigensolver needs numba (VLAB_KERNEL=numpy or numba missing)")
    if kernels is None or (compiled is None and size < _COMPILED_FROM):
        return np.linalg.eigh(A)
    flat = np.ascontiguousarray(A.reshape(size, 3, 3))
    w, V = np.empty((size, 3)), np.empty((size, 3, 3))
    from vlab import jit
    jit.call(kernels.eigh_batch, flat, w, V)
    return w.reshape(batch + (3,)), V.reshape(batch + (3, 3))
