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
    J3 = d0 * (d1 * d2 - a12 * a12) - a01 * (a01 * d2 - a12 * a02) + a02 * (a01 * a12 - d1 * a02)
    c3 = 0.5 * J3 * (3.0 / J2) ** 1.5
    c3 = min(1.0, max(-1.0, c3))
    alpha = math.acos(c3) / 3.0
    rad = 2.0 * math.sqrt(J2 / 3.0)
    if alpha < math.pi / 6.0:
        e1 = rad * math.cos(alpha)
    else:
        e1 = rad * math.cos(alpha + 2.0 * math.pi / 3.0)
    # rows of D − η₁ I
    r0 = (d0 - e1, a01, a02)
    r1 = (a01, d1 - e1, a12)
    r2 = (a02, a12, d2 - e1)
    n0 = r0[0] * r0[0] + r0[1] * r0[1] + r0[2] * r0[2]
    n1 = r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2]
    n2 = r2[0] * r2[0] + r2[1] * r2[1] + r2[2] * r2[2]
    if n0 >= n1 and n0 >= n2:
        p, q1, q2, npp = r0, r1, r2, n0
    elif n1 >= n2:
        p, q1, q2, npp = r1, r0, r2, n1
    else:
        p, q1, q2, npp = r2, r0, r1, n2
    inv = 1.0 / math.sqrt(npp)
    s10, s11, s12 = p[0] * inv, p[1] * inv, p[2] * inv
    c = s10 * q1[0] + s11 * q1[1] + s12 * q1[2]
    t10, t11, t12 = q1[0] - c * s10, q1[1] - c * s11, q1[2] - c * s12
    c = s10 * q2[0] + s11 * q2[1] + s12 * q2[2]
    t20, t21, t22 = q2[0] - c * s10, q2[1] - c * s11, q2[2] - c * s12
    m1 = t10 * t10 + t11 * t11 + t12 * t12
    m2 = t20 * t20 + t21 * t21 + t22 * t22
    if m1 >= m2:
        inv = 1.0 / math.sqrt(m1)
        s20, s21, s22 = t10 * inv, t11 * inv, t12 * inv
    else:
        inv = 1.0 / math.sqrt(m2)
        s20, s21, s22 = t20 * inv, t21 * inv, t22 * inv
    v10, v11, v12 = _cross(s10, s11, s12, s20, s21, s22)
    # the 2×2 problem of D on span{s1, s2}
    y0 = d0 * s10 + a01 * s11 + a02 * s12
    y1 = a01 * s10 + d1 * s11 + a12 * s12
    y2 = a02 * s10 + a12 * s11 + d2 * s12
    z0 = d0 * s20 + a01 * s21 + a02 * s22
    z1 = a01 * s20 + d1 * s21 + a12 * s22
    z2 = a02 * s20 + a12 * s21 + d2 * s22
    b11 = s10 * y0 + s11 * y1 + s12 * y2
    b12 = s20 * y0 + s21 * y1 + s22 * y2
    b22 = s20 * z0 + s21 * z1 + s22 * z2
    half = 0.5 * (b11 - b22)
    root = math.sqrt(half * half + b12 * b12)
    mid = 0.5 * (b11 + b22)
    e2, e3 = mid + root, mid - root
    # eigenvector of e2 in (s1, s2): perpendicular to the longer row of (b − e2 I)
    p0, p1 = b11 - e2, b12
    q0, q1_ = b12, b22 - e2
    if p0 * p0 + p1 * p1 >= q0 * q0 + q1_ * q1_:
        x0, x1 = -p1, p0
    else:
        x0, x1 = -q1_, q0
    nx = math.sqrt(x0 * x0 + x1 * x1)
    if nx == 0.0:
        x0, x1 = 1.0, 0.0
    else:
        x0, x1 = x0 / nx, x1 / nx
    v20, v21, v22 = x0 * s10 + x1 * s20, x0 * s11 + x1 * s21, x0 * s12 + x1 * s22
    v30, v31, v32 = _cross(v10, v11, v12, v20, v21, v22)
    l1, l2, l3 = (m + e1) * s, (m + e2) * s, (m + e3) * s
    # ascending: e3 <= e2 always; place e1
    if e1 >= e2:
        return (l3, l2, l1, v30, v20, v10, v31, v21, v11, v32, v22, v12)
    if e1 <= e3:
        return (l1, l3, l2, v10, v30, v20, v11, v31, v21, v12, v32, v22)
    return (l3, l1, l2, v30, v10, v20, v31, v11, v21, v32, v12, v22)


@numba.njit(**_OPTIONS)
def eigh_batch(A, w, V):
    """A (n,3,3) symmetric -> w (n,3) ascending, V (n,3,3) with V[p, :, k] the k-th vector."""
    for p in range(A.shape[0]):
        out = eig3(A[p, 0, 0], A[p, 0, 1], A[p, 0, 2], A[p, 1, 1], A[p, 1, 2], A[p, 2, 2])
        w[p, 0], w[p, 1], w[p, 2] = out[0], out[1], out[2]
        V[p, 0, 0], V[p, 0, 1], V[p, 0, 2] = out[3], out[4], out[5]
        V[p, 1, 0], V[p, 1, 1], V[p, 1, 2] = out[6], out[7], out[8]
        V[p, 2, 0], V[p, 2, 1], V[p, 2, 2] = out[9], out[10], out[11]


@numba.njit(**_OPTIONS)
def frame_batch(F, lam, N, n):
    """F (3,3,p) -> principal stretches lam (3,p), N[J, A, p] (eigenvectors of C = FᵀF) and
    n[i, A, p] = F N_A / λ_A."""
    for p in range(F.shape[2]):
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
'''

_KERNELS: list = []


def compiled_kernels():
    """The compiled module (``eig3``, ``eigh_batch``, ``frame_batch``), or None without numba."""
    if not _KERNELS:
        from vlab import jit  # numba starts on the first large batch, not with this module
        _KERNELS.append(jit.load("principal_eig", SOURCE) if jit.available() else None)
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
