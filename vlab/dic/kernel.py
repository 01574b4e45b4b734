"""The compiled IC-GN (vlab.jit): the loops of vlab.dic.icgn.prepare and refine over subsets, one
subset at a time, with the bicubic B-spline evaluated in place (no (n, P) temporaries).

Bicubic B-spline value at (x, y) from the coefficients c (scipy.ndimage.spline_filter, mode
"mirror"): with j₀ = ⌊x⌋, t = x − j₀ (likewise i₀, s for y),

    g(x, y) = Σ_{a,b=0..3} c[i₀−1+a, j₀−1+b] β_a(s) β_b(t),
    β₀ = (1−t)³/6,  β₁ = (3t³ − 6t² + 4)/6,  β₂ = (−3t³ + 3t² + 3t + 1)/6,  β₃ = t³/6

indices outside the image mirrored about the edge pixels (−k → k, (n−1)+k → (n−1)−k), as
scipy.ndimage.map_coordinates(order=3, mode="mirror", prefilter=False) does. The numpy twin is
vlab.dic.icgn._prepare_numpy and _refine_numpy (the reference of tests/test_dic_engine.py).
"""

from __future__ import annotations

SOURCE = '''
import math

import numpy as np
import numba

_OPTIONS = dict(cache=True, boundscheck=False, nogil=True, error_model="numpy")
OK, NO_TEXTURE, LEFT_IMAGE, NOT_CONVERGED = 0, 1, 2, 3


@numba.njit(inline="always", **_OPTIONS)
def _mirror(k, n):
    if k < 0:
        return -k
    if k > n - 1:
        return 2 * (n - 1) - k
    return k


@numba.njit(inline="always", **_OPTIONS)
def _weights(t):
    t2 = t * t
    t3 = t2 * t
    return ((1.0 - t) ** 3 / 6.0, (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
            (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0, t3 / 6.0)


@numba.njit(inline="always", **_OPTIONS)
def bspline3(c, x, y):
    h, w = c.shape
    j0 = int(math.floor(x))
    i0 = int(math.floor(y))
    wx = _weights(x - j0)
    wy = _weights(y - i0)
    total = 0.0
    for a in range(4):
        i = _mirror(i0 - 1 + a, h)
        row = 0.0
        for b in range(4):
            row += c[i, _mirror(j0 - 1 + b, w)] * wx[b]
        total += row * wy[a]
    return total


@numba.njit(**_OPTIONS)
def prepare_batch(f, fx, fy, cx, cy, half, fmean, df, H):
    side = 2 * half + 1
    P = side * side
    J = np.empty(6)
    for s in range(cx.size):
        x0 = cx[s]
        y0 = cy[s]
        total = 0.0
        for i in range(-half, half + 1):
            for j in range(-half, half + 1):
                total += f[y0 + i, x0 + j]
        m = total / P
        ss = 0.0
        for r in range(6):
            for cc in range(6):
                H[s, r, cc] = 0.0
        for i in range(-half, half + 1):
            for j in range(-half, half + 1):
                ss += (f[y0 + i, x0 + j] - m) ** 2
                gx = fx[y0 + i, x0 + j]
                gy = fy[y0 + i, x0 + j]
                J[0], J[1], J[2], J[3], J[4], J[5] = gx, gx * j, gx * i, gy, gy * j, gy * i
                for r in range(6):
                    for cc in range(r, 6):
                        H[s, r, cc] += J[r] * J[cc]
        for r in range(6):
            for cc in range(r):
                H[s, r, cc] = H[s, cc, r]
        fmean[s] = m
        df[s] = math.sqrt(ss)


@numba.njit(**_OPTIONS)
def refine_batch(f, fx, fy, c, cx, cy, half, fmean, df, Hinv, idx, p, tol, maxit, zncc, iters, status):
    h, w = c.shape
    side = 2 * half + 1
    P = side * side
    g = np.empty(P)
    b = np.empty(6)
    dp = np.empty(6)
    for k in range(idx.size):
        if status[k] != NOT_CONVERGED:
            continue
        s = idx[k]
        x0 = cx[s]
        y0 = cy[s]
        for it in range(1, maxit + 1):
            u, ux, uy, v, vx, vy = p[k, 0], p[k, 1], p[k, 2], p[k, 3], p[k, 4], p[k, 5]
            inside = True
            gs = 0.0
            q = 0
            for i in range(-half, half + 1):
                for j in range(-half, half + 1):
                    x = x0 + (1.0 + ux) * j + uy * i + u
                    y = y0 + vx * j + (1.0 + vy) * i + v
                    if x < 0.0 or x > w - 1 or y < 0.0 or y > h - 1:
                        inside = False
                    else:
                        g[q] = bspline3(c, x, y)
                        gs += g[q]
                    q += 1
            if not inside:
                status[k] = LEFT_IMAGE
                break
            gm = gs / P
            ss = 0.0
            for q in range(P):
                ss += (g[q] - gm) ** 2
            dg = math.sqrt(ss)
            if dg <= 0.0:
                status[k] = NO_TEXTURE
                break
            ratio = df[s] / dg
            for r in range(6):
                b[r] = 0.0
            ssd = 0.0
            q = 0
            for i in range(-half, half + 1):
                for j in range(-half, half + 1):
                    e = (f[y0 + i, x0 + j] - fmean[s]) - ratio * (g[q] - gm)
                    ssd += e * e
                    gx = fx[y0 + i, x0 + j] * e
                    gy = fy[y0 + i, x0 + j] * e
                    b[0] += gx
                    b[1] += gx * j
                    b[2] += gx * i
                    b[3] += gy
                    b[4] += gy * j
                    b[5] += gy * i
                    q += 1
            zncc[k] = 1.0 - 0.5 * ssd / (df[s] * df[s])
            for r in range(6):
                acc = 0.0
                for cc in range(6):
                    acc += Hinv[s, r, cc] * b[cc]
                dp[r] = -acc
            # W(p) <- W(p) W(dp)^-1, affine: inverse of [[A, t], [0, 1]] is [[A^-1, -A^-1 t], [0, 1]]
            a11, a12, a21, a22 = 1.0 + dp[1], dp[2], dp[4], 1.0 + dp[5]
            det = a11 * a22 - a12 * a21
            i11, i12, i21, i22 = a22 / det, -a12 / det, -a21 / det, a11 / det
            t1 = -(i11 * dp[0] + i12 * dp[3])
            t2 = -(i21 * dp[0] + i22 * dp[3])
            m11, m12, m21, m22 = 1.0 + ux, uy, vx, 1.0 + vy
            p[k, 0] = m11 * t1 + m12 * t2 + u
            p[k, 1] = m11 * i11 + m12 * i21 - 1.0
            p[k, 2] = m11 * i12 + m12 * i22
            p[k, 3] = m21 * t1 + m22 * t2 + v
            p[k, 4] = m21 * i11 + m22 * i21
            p[k, 5] = m21 * i12 + m22 * i22 - 1.0
            iters[k] = it
            norm = (dp[0] ** 2 + dp[3] ** 2 + half * half * (dp[1] ** 2 + dp[2] ** 2 + dp[4] ** 2 + dp[5] ** 2))
            if math.sqrt(norm) < tol:
                status[k] = OK
                break
'''

_KERNELS: list = []


def compiled_kernels():
    """The compiled module (``prepare_batch``, ``refine_batch``), or None without numba (or VLAB_KERNEL=numpy)."""
    if not _KERNELS:
        from vlab import jit, settings  # numba starts on the first correlation, not with this module
        _KERNELS.append(jit.load("dic_icgn", SOURCE) if jit.available(settings.current()) else None)
    return _KERNELS[0]
