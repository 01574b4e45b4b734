"""The compiled camera (vlab.jit): the loops of vlab.dic.inverse_map.reference_points and
vlab.dic.speckle.intensity, one sub-sample at a time, without (n, slots) temporaries.

``invert_grid`` visits, per face cell, the grid points of its deformed bounding box
(vlab.dic.inverse_map.cell_boxes, computed once in numpy for both twins) not yet claimed, solves
x(ξ) = x by Newton (per point, until |Δξ| + |Δη| < 1e-13, at most 30 steps) and keeps X(ξ) if ξ
lies in the cell (within 1e-9), with the shape functions of vlab.dic.inverse_map: quadrilaterals
of 4 (bilinear), 8 (serendipity) or 9 (biquadratic) nodes at ``nodes`` (ξ_a, η_a) = corners
(−1,−1), (1,−1), (1,1), (−1,1), mid-edges (0,−1), (1,0), (0,1), (−1,0), centre (0,0); triangles
of 3 (L = (1 − ξ − η, ξ, η)) or 6 nodes (L_a (2 L_a − 1), then 4 L_a L_b on the edges (0,1),
(1,2), (2,0)). ``pixel_means`` averages each pixel's s × s sub-samples of
I = d + (b − d) exp(−κ Σ_k exp(−|X − X_k|²/r²)) (the background off the face), summed over the
speckles within CUTOFF · r, read from the 3 × 3 cells around X of vlab.dic.speckle.cell_table.
The numpy twins (the reference of tests/test_dic_camera.py) are reference_points and
vlab.dic.camera._pixel_means_numpy.
"""

from __future__ import annotations

SOURCE = '''
import math

import numpy as np
import numba

_OPTIONS = dict(cache=True, boundscheck=False, nogil=True, error_model="numpy")


@numba.njit(inline="always", **_OPTIONS)
def _lagrange2(node, t):
    if node == 0.0:
        return 1.0 - t * t, -2.0 * t
    return 0.5 * t * (t + node), t + 0.5 * node


@numba.njit(inline="always", **_OPTIONS)
def _triangle(k, xi, eta, N, Nxi, Neta):
    L0, L1, L2 = 1.0 - xi - eta, xi, eta
    if k == 3:
        N[0], N[1], N[2] = L0, L1, L2
        Nxi[0], Nxi[1], Nxi[2] = -1.0, 1.0, 0.0
        Neta[0], Neta[1], Neta[2] = -1.0, 0.0, 1.0
        return
    N[0], N[1], N[2] = L0 * (2.0 * L0 - 1.0), L1 * (2.0 * L1 - 1.0), L2 * (2.0 * L2 - 1.0)
    N[3], N[4], N[5] = 4.0 * L0 * L1, 4.0 * L1 * L2, 4.0 * L2 * L0
    Nxi[0], Nxi[1], Nxi[2] = -(4.0 * L0 - 1.0), 4.0 * L1 - 1.0, 0.0
    Nxi[3], Nxi[4], Nxi[5] = 4.0 * (L0 - L1), 4.0 * L2, -4.0 * L2
    Neta[0], Neta[1], Neta[2] = -(4.0 * L0 - 1.0), 0.0, 4.0 * L2 - 1.0
    Neta[3], Neta[4], Neta[5] = -4.0 * L1, 4.0 * L1, 4.0 * (L0 - L2)


@numba.njit(inline="always", **_OPTIONS)
def _shape(k, nodes, xi, eta, N, Nxi, Neta):
    if k == 3 or k == 6:
        _triangle(k, xi, eta, N, Nxi, Neta)
        return
    if k == 4:  # written out: the bilinear cell is the common one, and the loop below costs 30 % more
        a0, a1, b0, b1 = 1.0 - xi, 1.0 + xi, 1.0 - eta, 1.0 + eta
        N[0], N[1], N[2], N[3] = 0.25 * a0 * b0, 0.25 * a1 * b0, 0.25 * a1 * b1, 0.25 * a0 * b1
        Nxi[0], Nxi[1], Nxi[2], Nxi[3] = -0.25 * b0, 0.25 * b0, 0.25 * b1, -0.25 * b1
        Neta[0], Neta[1], Neta[2], Neta[3] = -0.25 * a0, -0.25 * a1, 0.25 * a1, 0.25 * a0
        return
    for a in range(k):
        p, q = nodes[a, 0], nodes[a, 1]
        if k == 9:
            lx, dlx = _lagrange2(p, xi)
            ly, dly = _lagrange2(q, eta)
            N[a], Nxi[a], Neta[a] = lx * ly, dlx * ly, lx * dly
        elif p != 0.0 and q != 0.0:  # 8-node serendipity: a corner
            sx, sy = 1.0 + p * xi, 1.0 + q * eta
            N[a] = 0.25 * sx * sy * (p * xi + q * eta - 1.0)
            Nxi[a], Neta[a] = 0.25 * p * sy * (2.0 * p * xi + q * eta), 0.25 * q * sx * (p * xi + 2.0 * q * eta)
        elif p == 0.0:
            sy = 1.0 + q * eta
            N[a], Nxi[a], Neta[a] = 0.5 * (1.0 - xi * xi) * sy, -xi * sy, 0.5 * q * (1.0 - xi * xi)
        else:
            sx = 1.0 + p * xi
            N[a], Nxi[a], Neta[a] = 0.5 * sx * (1.0 - eta * eta), 0.5 * p * (1.0 - eta * eta), -eta * sx


@numba.njit(**_OPTIONS)
def invert_grid(X, x, cells, boxes, nodes, xs, neg_ys, PX, PY, hit):
    k = cells.shape[1]
    N = np.empty(k)
    Nxi = np.empty(k)
    Neta = np.empty(k)
    triangle = k == 3 or k == 6
    start = 1.0 / 3.0 if triangle else 0.0
    for c in range(cells.shape[0]):
        x0, x1, y0, y1 = boxes[c, 0], boxes[c, 1], boxes[c, 2], boxes[c, 3]
        j0, j1 = np.searchsorted(xs, x0, "left"), np.searchsorted(xs, x1, "right")
        i0, i1 = np.searchsorted(neg_ys, -y1, "left"), np.searchsorted(neg_ys, -y0, "right")
        for i in range(i0, i1):
            py = -neg_ys[i]
            for j in range(j0, j1):
                if hit[i, j]:
                    continue
                px = xs[j]
                xi, eta = start, start
                for _ in range(30):
                    _shape(k, nodes, xi, eta, N, Nxi, Neta)
                    rx, ry, ja, jb, jc, jd = -px, -py, 0.0, 0.0, 0.0, 0.0
                    for a in range(k):
                        n = cells[c, a]
                        rx += N[a] * x[n, 0]
                        ry += N[a] * x[n, 1]
                        ja += Nxi[a] * x[n, 0]
                        jb += Neta[a] * x[n, 0]
                        jc += Nxi[a] * x[n, 1]
                        jd += Neta[a] * x[n, 1]
                    det = ja * jd - jb * jc
                    dxi, deta = (jd * rx - jb * ry) / det, (ja * ry - jc * rx) / det
                    xi, eta = xi - dxi, eta - deta
                    if not (abs(dxi) + abs(deta) >= 1e-13):  # converged (or NaN: refused below)
                        break
                if triangle:
                    inside = xi >= -1e-9 and eta >= -1e-9 and xi + eta <= 1.0 + 1e-9
                else:
                    inside = abs(xi) <= 1.0 + 1e-9 and abs(eta) <= 1.0 + 1e-9
                if inside:
                    _shape(k, nodes, xi, eta, N, Nxi, Neta)
                    sx, sy = 0.0, 0.0
                    for a in range(k):
                        sx += N[a] * X[cells[c, a], 0]
                        sy += N[a] * X[cells[c, a], 1]
                    PX[i, j], PY[i, j], hit[i, j] = sx, sy, True


@numba.njit(inline="always", **_OPTIONS)
def _intensity(table, ox, oy, cell, ncx, ncy, inv_r2, cut2, b, d, kappa, x, y):
        cx = int(math.floor((x - ox) / cell))
        cy = int(math.floor((y - oy) / cell))
        total = 0.0
        for ky in range(max(cy - 1, 0), min(cy + 2, ncy)):
            for kx in range(max(cx - 1, 0), min(cx + 2, ncx)):
                row = ky * ncx + kx
                for s in range(table.shape[1]):
                    sx = table[row, s, 0]
                    if sx == np.inf:
                        break
                    q = ((sx - x) ** 2 + (table[row, s, 1] - y) ** 2) * inv_r2
                    if q <= cut2:
                        total += math.exp(-q)
        return d + (b - d) * math.exp(-kappa * total)


@numba.njit(**_OPTIONS)
def pixel_means(table, ox, oy, cell, ncx, ncy, inv_r2, cut2, b, d, kappa, PX, PY, hit, background, s, out):
    """out[i, j] = mean over the s × s sub-samples of pixel (i, j) of I(PX, PY) where hit, else
    the background."""
    weight = 1.0 / (s * s)
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            total = 0.0
            for a in range(i * s, i * s + s):
                for c in range(j * s, j * s + s):
                    if hit[a, c]:
                        total += _intensity(table, ox, oy, cell, ncx, ncy, inv_r2, cut2, b, d, kappa,
                                            PX[a, c], PY[a, c])
                    else:
                        total += background
            out[i, j] = total * weight
'''

_KERNELS: list = []


def compiled_kernels():
    """The compiled module (``invert_grid``, ``pixel_means``), or None without numba (or VLAB_KERNEL=numpy)."""
    if not _KERNELS:
        from vlab import jit, settings  # numba starts on the first render, not with this module
        _KERNELS.append(jit.load("dic_camera", SOURCE) if jit.available(settings.current()) else None)
    return _KERNELS[0]
