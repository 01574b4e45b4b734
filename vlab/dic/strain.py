"""The strain window: Green–Lagrange strain from a local least-squares plane fit of u and v.

At each grid point the displacements of the valid subsets within the w × w window of grid points
around it (truncated at the grid's edges and where subsets failed) are fitted by planes

    u ≈ a + u_x (X − X₀) + u_y (Y − Y₀),   v ≈ b + v_x (X − X₀) + v_y (Y − Y₀)

(X, Y the subset centres in the reference image, px), and the strain is Green–Lagrange,
E = ½ (Fᵀ F − I) with F = I + ∇u, in image axes (x right, y down):

    E_xx = u_x + ½ (u_x² + v_x²),  E_yy = v_y + ½ (u_y² + v_y²),  E_xy = ½ (u_y + v_x + u_x u_y + v_x v_y)

NaN where the centre subset failed or fewer than MIN_POINTS valid subsets span the window.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

MIN_POINTS = 4


def gradient_window(U: np.ndarray, V: np.ndarray, step: float, window: int) -> tuple[np.ndarray, ...]:
    """(u_x, u_y, v_x, v_y) on the grid of U, V (rows = y, columns = x, NaN = failed)."""
    half = window // 2
    o = np.arange(-half, half + 1) * float(step)
    KY, KX = np.meshgrid(o, o, indexing="ij")
    ones = np.ones_like(KX)
    valid = np.isfinite(U) & np.isfinite(V)
    m = valid.astype(float)
    u, v = np.where(valid, U, 0.0), np.where(valid, V, 0.0)

    def S(a, k):  # Σ over the window of a(neighbour) · k(offset)
        return ndimage.correlate(a, k, mode="constant", cval=0.0)

    n, sx, sy = S(m, ones), S(m, KX), S(m, KY)
    sxx, sxy, syy = S(m, KX * KX), S(m, KX * KY), S(m, KY * KY)
    A = np.stack([np.stack([n, sx, sy], -1), np.stack([sx, sxx, sxy], -1), np.stack([sy, sxy, syy], -1)], -2)
    rhs_u = np.stack([S(u, ones), S(u, KX), S(u, KY)], -1)
    rhs_v = np.stack([S(v, ones), S(v, KX), S(v, KY)], -1)
    det = np.linalg.det(A)
    ok = valid & (n >= MIN_POINTS) & (np.abs(det) > 1e-9 * np.maximum(n, 1) ** 3 * float(step) ** 4)
    out = [np.full(U.shape, np.nan) for _ in range(4)]
    if ok.any():
        cu = np.linalg.solve(A[ok], rhs_u[ok][..., None])[..., 0]
        cv = np.linalg.solve(A[ok], rhs_v[ok][..., None])[..., 0]
        out[0][ok], out[1][ok], out[2][ok], out[3][ok] = cu[:, 1], cu[:, 2], cv[:, 1], cv[:, 2]
    return tuple(out)


def green_lagrange(ux, uy, vx, vy) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(E_xx, E_yy, E_xy) of the displacement gradient."""
    exx = ux + 0.5 * (ux * ux + vx * vx)
    eyy = vy + 0.5 * (uy * uy + vy * vy)
    exy = 0.5 * (uy + vx + ux * uy + vx * vy)
    return exx, eyy, exy


def strain_window(U: np.ndarray, V: np.ndarray, step: float, window: int) -> tuple[np.ndarray, ...]:
    """(E_xx, E_yy, E_xy) on the grid from the strain window (see the module docstring)."""
    return green_lagrange(*gradient_window(U, V, step, window))
