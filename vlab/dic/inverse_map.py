"""The inverse of an FE deformation on a flat face: the reference point X of a current point x.

Each cell maps its isoparametric coordinates ξ = (ξ, η) to the reference and the current plane
with the same shape functions N_a(ξ):

    X(ξ) = Σ_a N_a(ξ) X_a,   x(ξ) = Σ_a N_a(ξ) (X_a + u_a)

the cell's nodes listed as vlab.dic.face gives them (corners (ξ_a, η_a) = (−1,−1), (1,−1), (1,1),
(−1,1) counter-clockwise, then the mid-edge nodes (0,−1), (1,0), (0,1), (−1,0), then the centre):

- 4-node bilinear quadrilateral: N_a = ¼ (1 + ξ ξ_a)(1 + η η_a);
- 9-node biquadratic: N_a = l_{ξ_a}(ξ) l_{η_a}(η), l₋₁(t) = t (t − 1)/2, l₀ = 1 − t², l₁ = t (t + 1)/2;
- 8-node serendipity: corners ¼ (1 + ξ ξ_a)(1 + η η_a)(ξ ξ_a + η η_a − 1), mid-edge nodes
  ½ (1 − ξ²)(1 + η η_a) (ξ_a = 0) or ½ (1 + ξ ξ_a)(1 − η²) (η_a = 0);
- 3-node triangle: N = L = (1 − ξ − η, ξ, η); 6-node: L_a (2 L_a − 1) at the corners and
  4 L_a L_b on the edges (0,1), (1,2), (2,0).

A point x is located in the deformed cells whose bounding box holds it (the box of the cell's
Bernstein control points, vlab.dic.inverse_map.cell_boxes, which holds a curved quadratic cell
whole), x(ξ) = x is solved by Newton's method (ξ ← ξ − J⁻¹ (x(ξ) − x), J = ∂x/∂ξ, from the
cell's centre), the cell whose solution lies inside it (within 1e-9) is kept, and X = X(ξ). For a
displacement the cells interpolate exactly (homogeneous on straight-sided cells; quadratic on
quadratic cells) this inverse is exact to round-off; otherwise it is the inverse of the FE
interpolation of u, which is what the FE solution defines.

The points are the sub-samples of a camera's pixels: a regular grid, given by its axes (``xs``
ascending along e₁, ``ys`` along e₂ in either order), so each cell visits only the grid points of
its bounding box (a cell costs one vectorised Newton solve over those points). The compiled twin
(vlab.dic.camera_kernel.invert_grid) runs the same loop point by point.
"""

from __future__ import annotations

import numpy as np

NEWTON_ITERATIONS = 30
NEWTON_TOL = 1e-13  # on |Δξ|: round-off of the isoparametric coordinates
INSIDE_TOL = 1e-9  # on ξ: a point on a shared edge belongs to the first cell found
TRIANGLES = (3, 6)
NODES = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0],  # corners, mid-edges, centre
                  [0.0, -1.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, 0.0]])
# Bernstein control points of a quadratic: from the values at t = −1, 0, 1 (rows: control points)
TO_BERNSTEIN = np.array([[1.0, 0.0, 0.0], [-0.5, 2.0, -0.5], [0.0, 0.0, 1.0]])
GRID = np.array([[0, 7, 3], [4, 8, 6], [1, 5, 2]])  # node at (ξ, η) = (i − 1, j − 1)


def shape_functions(k: int, xi: np.ndarray, eta: np.ndarray) -> tuple[np.ndarray, ...]:
    """(N, ∂N/∂ξ, ∂N/∂η), each (k, n), for k = 3, 6 (triangles) or 4, 8, 9 (quadrilaterals)."""
    if k in TRIANGLES:
        return _triangle(k, xi, eta)
    a, b = NODES[:k, :1], NODES[:k, 1:]
    if k == 4:
        sx, sy = 1 + a * xi, 1 + b * eta
        return 0.25 * sx * sy, 0.25 * a * sy, 0.25 * sx * b
    if k == 9:
        (lx, dlx), (ly, dly) = _lagrange2(a, xi), _lagrange2(b, eta)
        return lx * ly, dlx * ly, lx * dly
    sx, sy = 1 + a * xi, 1 + b * eta  # the 8-node serendipity quadrilateral
    corner, on_xi = a * b != 0, a == 0  # a corner; a mid-edge node on an edge along ξ
    qx, qy = 1 - xi ** 2, 1 - eta ** 2

    def pick(at_corner, along_xi, along_eta):
        return np.where(corner, at_corner, np.where(on_xi, along_xi, along_eta))
    return (pick(0.25 * sx * sy * (a * xi + b * eta - 1), 0.5 * qx * sy, 0.5 * sx * qy),
            pick(0.25 * a * sy * (2 * a * xi + b * eta), -xi * sy, 0.5 * a * qy),
            pick(0.25 * b * sx * (a * xi + 2 * b * eta), 0.5 * b * qx, -eta * sx))


def _lagrange2(node: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The 1-D quadratic Lagrange function of the node at −1, 0 or 1 (rows) at t, and its derivative."""
    value = np.where(node == 0, 1 - t * t, 0.5 * t * (t + node))
    return value, np.where(node == 0, -2 * t, t + 0.5 * node)


def _triangle(k: int, xi: np.ndarray, eta: np.ndarray) -> tuple[np.ndarray, ...]:
    one, zero = np.ones_like(xi), np.zeros_like(xi)
    L, dLx, dLy = np.stack([1 - xi - eta, xi, eta]), np.stack([-one, one, zero]), np.stack([-one, zero, one])
    if k == 3:
        return L, dLx, dLy
    b = [1, 2, 0]  # the edges (0,1), (1,2), (2,0)
    return (np.concatenate([L * (2 * L - 1), 4 * L * L[b]]),
            np.concatenate([(4 * L - 1) * dLx, 4 * (dLx * L[b] + L * dLx[b])]),
            np.concatenate([(4 * L - 1) * dLy, 4 * (dLy * L[b] + L * dLy[b])]))


def cell_boxes(x: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """(m, 4) [x_min, x_max, y_min, y_max] of each cell's Bernstein control points (mm), whose
    convex hull holds the cell: its nodes for straight-sided cells; for a 6-node triangle the
    corners and 2 x_m − (x_a + x_b)/2 per edge; for a 9-node quadrilateral TO_BERNSTEIN applied
    along ξ and η to the 3 × 3 node grid (an 8-node one first gets the centre its serendipity
    map passes through, ½ Σ mid-edge − ¼ Σ corner, so its Q2 interpolant is the same map)."""
    xc = np.asarray(x, float)[cells]
    k = cells.shape[1]
    if k == 6:
        xc = np.concatenate([xc[:, :3], 2 * xc[:, 3:] - 0.5 * (xc[:, :3] + xc[:, [1, 2, 0]])], axis=1)
    elif k in (8, 9):
        if k == 8:
            xc = np.concatenate([xc, (0.5 * xc[:, 4:].sum(axis=1) - 0.25 * xc[:, :4].sum(axis=1))[:, None]], axis=1)
        xc = np.einsum("ai,mijd,bj->mabd", TO_BERNSTEIN, xc[:, GRID], TO_BERNSTEIN).reshape(len(cells), 9, 2)
    lo, hi = xc.min(axis=1), xc.max(axis=1)
    return np.ascontiguousarray(np.stack([lo[:, 0], hi[:, 0], lo[:, 1], hi[:, 1]], axis=1))


def _inside(k: int, xi: np.ndarray, eta: np.ndarray) -> np.ndarray:
    if k in TRIANGLES:
        return (xi >= -INSIDE_TOL) & (eta >= -INSIDE_TOL) & (xi + eta <= 1 + INSIDE_TOL)
    return (np.abs(xi) <= 1 + INSIDE_TOL) & (np.abs(eta) <= 1 + INSIDE_TOL)


def invert_cell(x_cell: np.ndarray, px: np.ndarray, py: np.ndarray) -> tuple[np.ndarray, ...]:
    """Isoparametric coordinates (ξ, η) of the points (px, py) in the cell of current corners
    ``x_cell`` (k, 2), and whether each lies inside it (Newton converged and ξ in the cell)."""
    k = len(x_cell)
    xi = np.full(px.shape, 1 / 3 if k in TRIANGLES else 0.0)
    eta = xi.copy()
    for _ in range(NEWTON_ITERATIONS):
        N, Nxi, Neta = shape_functions(k, xi, eta)
        rx, ry = x_cell[:, 0] @ N - px, x_cell[:, 1] @ N - py
        a, b = x_cell[:, 0] @ Nxi, x_cell[:, 0] @ Neta
        c, d = x_cell[:, 1] @ Nxi, x_cell[:, 1] @ Neta
        det = a * d - b * c
        dxi, deta = (d * rx - b * ry) / det, (a * ry - c * rx) / det
        xi, eta = xi - dxi, eta - deta
        if k == 3 or np.max(np.abs(dxi) + np.abs(deta), initial=0.0) < NEWTON_TOL:
            break  # a triangle's map is affine: one step is exact
    ok = np.isfinite(xi) & np.isfinite(eta) & _inside(k, xi, eta)
    return xi, eta, ok


def reference_points(X: np.ndarray, x: np.ndarray, cells: np.ndarray, xs: np.ndarray,
                     ys: np.ndarray, compiled: bool | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Reference coordinates (PX, PY), each (len(ys), len(xs)) mm, of the grid points
    (xs[j], ys[i]) of the current face, and ``hit`` (same shape): the point lies on the face.
    X, x: (n, 2) reference and current node coordinates; cells: (m, k) as vlab.dic.face lists them.
    ``compiled``: None uses the numba kernel when available, False the numpy loop, True insists."""
    from vlab.dic.camera_kernel import compiled_kernels

    kernels = compiled_kernels() if compiled is not False else None
    if compiled and kernels is None:
        raise RuntimeError("the compiled camera needs numba (VLAB_KERNEL=numpy or numba missing)")
    PX = np.full((len(ys), len(xs)), np.nan)
    PY = np.full_like(PX, np.nan)
    hit = np.zeros(PX.shape, bool)
    boxes = cell_boxes(x, cells)
    if kernels is not None:
        return _compiled(kernels, X, x, cells, boxes, xs, ys, PX, PY, hit)
    descending = len(ys) > 1 and ys[0] > ys[-1]
    ys_up = ys[::-1] if descending else ys
    for cell, (x0, x1, y0, y1) in zip(cells, boxes):
        xc = x[cell]
        j0, j1 = np.searchsorted(xs, x0, "left"), np.searchsorted(xs, x1, "right")
        i0, i1 = np.searchsorted(ys_up, y0, "left"), np.searchsorted(ys_up, y1, "right")
        if j0 >= j1 or i0 >= i1:
            continue
        rows = slice(len(ys) - i1, len(ys) - i0) if descending else slice(i0, i1)
        gx, gy = np.meshgrid(xs[j0:j1], ys[rows])
        free = ~hit[rows, j0:j1]
        xi, eta, ok = invert_cell(xc, gx[free], gy[free])
        N = shape_functions(len(cell), xi[ok], eta[ok])[0]
        block_x, block_y, block_hit = PX[rows, j0:j1], PY[rows, j0:j1], hit[rows, j0:j1]
        idx = np.flatnonzero(free)[ok]
        block_x.flat[idx], block_y.flat[idx] = X[cell, 0] @ N, X[cell, 1] @ N
        block_hit.flat[idx] = True
    return PX, PY, hit


def _compiled(kernels, X, x, cells, boxes, xs, ys, PX, PY, hit):
    """reference_points by the kernel, which takes the rows' ys descending (as a camera's are)."""
    from vlab import jit

    ascending = len(ys) > 1 and ys[0] < ys[-1]
    rows = slice(None, None, -1) if ascending else slice(None)
    jit.call(kernels.invert_grid, _f64(X), _f64(x), np.ascontiguousarray(cells, dtype=np.int64), boxes, NODES, _f64(xs),
             _f64(-np.asarray(ys)[rows]), PX, PY, hit)
    return PX[rows], PY[rows], hit[rows]


def _f64(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64)
