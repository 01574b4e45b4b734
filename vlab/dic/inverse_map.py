"""The inverse of an FE deformation on a flat face: the reference point X of a current point x.

Each cell maps its isoparametric coordinates ξ = (ξ, η) to the reference and the current plane
with the same shape functions N_a(ξ):

    X(ξ) = Σ_a N_a(ξ) X_a,   x(ξ) = Σ_a N_a(ξ) (X_a + u_a)

bilinear quadrilaterals N_a = ¼ (1 + ξ ξ_a)(1 + η η_a) (corners (∓1, ∓1) counter-clockwise) and
linear triangles N = (1 − ξ − η, ξ, η). A point x is located in the deformed cells whose bounding
box holds it, x(ξ) = x is solved by Newton's method (ξ ← ξ − J⁻¹ (x(ξ) − x), J = ∂x/∂ξ, from the
cell's centre), the cell whose solution lies inside it (within 1e-9) is kept, and X = X(ξ). For a
homogeneous deformation of straight-sided cells this inverse is exact to round-off; otherwise it
is the inverse of the FE interpolation of u, which is what the FE solution defines.

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
CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


def shape_functions(k: int, xi: np.ndarray, eta: np.ndarray) -> tuple[np.ndarray, ...]:
    """(N, ∂N/∂ξ, ∂N/∂η), each (k, n), for k = 3 (linear triangle) or 4 (bilinear quadrilateral)."""
    if k == 3:
        one, zero = np.ones_like(xi), np.zeros_like(xi)
        return (np.stack([1 - xi - eta, xi, eta]), np.stack([-one, one, zero]), np.stack([-one, zero, one]))
    a, b = CORNERS[:, :1], CORNERS[:, 1:]
    sx, sy = 1 + a * xi, 1 + b * eta
    return 0.25 * sx * sy, 0.25 * a * sy, 0.25 * sx * b


def _inside(k: int, xi: np.ndarray, eta: np.ndarray) -> np.ndarray:
    if k == 3:
        return (xi >= -INSIDE_TOL) & (eta >= -INSIDE_TOL) & (xi + eta <= 1 + INSIDE_TOL)
    return (np.abs(xi) <= 1 + INSIDE_TOL) & (np.abs(eta) <= 1 + INSIDE_TOL)


def invert_cell(x_cell: np.ndarray, px: np.ndarray, py: np.ndarray) -> tuple[np.ndarray, ...]:
    """Isoparametric coordinates (ξ, η) of the points (px, py) in the cell of current corners
    ``x_cell`` (k, 2), and whether each lies inside it (Newton converged and ξ in the cell)."""
    k = len(x_cell)
    xi = np.full(px.shape, 1 / 3 if k == 3 else 0.0)
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
    X, x: (n, 2) reference and current node coordinates; cells: (m, 3 | 4) counter-clockwise.
    ``compiled``: None uses the numba kernel when available, False the numpy loop, True insists."""
    from vlab.dic.camera_kernel import compiled_kernels

    kernels = compiled_kernels() if compiled is not False else None
    if compiled and kernels is None:
        raise RuntimeError("the compiled camera needs numba (VLAB_KERNEL=numpy or numba missing)")
    PX = np.full((len(ys), len(xs)), np.nan)
    PY = np.full_like(PX, np.nan)
    hit = np.zeros(PX.shape, bool)
    if kernels is not None:
        return _compiled(kernels, X, x, cells, xs, ys, PX, PY, hit)
    descending = len(ys) > 1 and ys[0] > ys[-1]
    ys_up = ys[::-1] if descending else ys
    for cell in cells:
        xc = x[cell]
        (x0, y0), (x1, y1) = xc.min(axis=0), xc.max(axis=0)
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


def _compiled(kernels, X, x, cells, xs, ys, PX, PY, hit):
    """reference_points by the kernel, which takes the rows' ys descending (as a camera's are)."""
    from vlab import jit

    ascending = len(ys) > 1 and ys[0] < ys[-1]
    rows = slice(None, None, -1) if ascending else slice(None)
    jit.call(kernels.invert_grid, _f64(X), _f64(x), np.ascontiguousarray(cells, dtype=np.int64), _f64(xs),
             _f64(-np.asarray(ys)[rows]), PX, PY, hit)
    return PX[rows], PY[rows], hit[rows]


def _f64(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64)
