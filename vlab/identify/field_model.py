"""The FE's strain maps as the DIC sees them: the FE displacement averaged over each subset, passed
through the DIC's own strain window (vlab.dic.strain) — the FE field "levelled".

Subset centre (x, y) px → face point X = (c₁ + (x − (W − 1)/2) p, c₂ − (y − (H − 1)/2) p) mm
(vlab.dic.camera's pixel centres), located in the reference face cell holding it (isoparametric
coordinates ξ by Newton's method, vlab.dic.inverse_map), so the FE displacement there is the
interpolation u(X) = Σ_a N_a(ξ) u_a over the cell's vertices; a subset's is the mean of u over
its pixel centres on the face (the subset's affine fit, to first order): a fixed sparse matrix P
(subsets × face vertices). In image pixels (y down) U = P u₁ / p, V = −P u₂ / p. The strain window fits planes
to U, V over the same valid subsets as the DIC (a linear operator G on (U, V) for a fixed mask) and
forms the Green–Lagrange strain of its gradients:

    E_xx = u_x + ½ (u_x² + v_x²),  E_yy = v_y + ½ (u_y² + v_y²),  E_xy = ½ (u_y + v_x + u_x u_y + v_x v_y)

so the sensitivities are exact: ∂(u_x, u_y, v_x, v_y)/∂p = G (P ∂u/∂p), chained through

    ∂E_xx = (1 + u_x) ∂u_x + v_x ∂v_x,  ∂E_yy = u_y ∂u_y + (1 + v_y) ∂v_y,
    ∂E_xy = ½ ((1 + u_x) ∂u_y + u_y ∂u_x + (1 + v_y) ∂v_x + v_x ∂v_y).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage, sparse

from vlab.dic.inverse_map import invert_cell, shape_functions
from vlab.dic.strain import gradient_window

__all__ = ["face_points", "interpolation", "subset_interpolation", "levelled", "usable"]


def face_points(camera: dict, xs: np.ndarray, ys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(X₁, X₂) mm of the grid's subset centres (rows = ys, columns = xs)."""
    (W, H), p, (c1, c2) = camera["pixels"], camera["mm_per_px"], camera["centre"]
    X, Y = np.meshgrid(xs, ys)
    return c1 + (X - (W - 1) / 2) * p, c2 - (Y - (H - 1) / 2) * p


def interpolation(face, X1: np.ndarray, X2: np.ndarray) -> tuple[sparse.csr_matrix, np.ndarray]:
    """(P (n, n_face_vertices), found (n,)) for the points (X₁, X₂) flattened: row i holds N_a(ξ)
    of the reference cell holding point i (empty where no cell does)."""
    x1, x2 = np.ravel(X1), np.ravel(X2)
    owner = np.full(x1.size, -1)
    weights = np.zeros((x1.size, face.cells.shape[1]))
    for c, cell in enumerate(face.cells):
        Xc = face.X[cell]
        lo, hi = Xc.min(axis=0), Xc.max(axis=0)
        idx = np.flatnonzero((owner < 0) & (x1 >= lo[0] - 1e-12) & (x1 <= hi[0] + 1e-12)
                             & (x2 >= lo[1] - 1e-12) & (x2 <= hi[1] + 1e-12))
        if idx.size == 0:
            continue
        xi, eta, inside = invert_cell(Xc, x1[idx], x2[idx])
        idx, xi, eta = idx[inside], xi[inside], eta[inside]
        owner[idx] = c
        weights[idx] = shape_functions(len(cell), xi, eta)[0].T
    found = owner >= 0
    rows = np.repeat(np.flatnonzero(found), face.cells.shape[1])
    cols = face.cells[owner[found]].ravel()
    P = sparse.csr_matrix((weights[found].ravel(), (rows, cols)), shape=(x1.size, len(face.nodes)))
    return P, found


def subset_interpolation(face, X1: np.ndarray, X2: np.ndarray, subset: int, pitch: float):
    """(P, found) of the subsets centred at (X₁, X₂): row i the mean of the interpolation over the
    subset's subset × subset pixel centres on the face (the translation of the least-squares affine
    fit of u over a square subset is that mean, which is what IC-GN's affine subset measures to
    first order); found where the centre is on the face. subset 0: the centres alone."""
    P0, found = interpolation(face, X1, X2)
    if subset <= 1:
        return P0, found
    o = (np.arange(subset) - (subset - 1) / 2) * pitch
    dx, dy = (a.ravel() for a in np.meshgrid(o, -o))
    x1 = (np.ravel(X1)[:, None] + dx).ravel()
    x2 = (np.ravel(X2)[:, None] + dy).ravel()
    Ps, on = interpolation(face, x1, x2)
    count = on.reshape(-1, dx.size).sum(axis=1)
    owner = np.repeat(np.arange(found.size), dx.size)
    mean = sparse.csr_matrix((1.0 / np.maximum(count[owner], 1), (owner, np.arange(owner.size))),
                             shape=(found.size, owner.size))
    return (mean @ Ps).tocsr(), found


def usable(valid: np.ndarray, on_face: np.ndarray, window: int) -> np.ndarray:
    """Grid points whose strain window holds no valid subset off the face: there the levelled FE
    strain uses exactly the DIC's subsets, so the two are comparable."""
    stray = (valid & ~on_face).astype(float)
    near = ndimage.correlate(stray, np.ones((window, window)), mode="constant", cval=0.0) > 0
    return valid & on_face & ~near


def _gradients(P, u: np.ndarray, mask: np.ndarray, pitch: float, step: float, window: int):
    """(u_x, u_y, v_x, v_y) of the strain window on the FE displacement u (n_face, 2) mm at the
    masked subsets (elsewhere NaN, so the window sees the DIC's valid set)."""
    U = np.where(mask, (P @ u[:, 0]).reshape(mask.shape) / pitch, np.nan)
    V = np.where(mask, -(P @ u[:, 1]).reshape(mask.shape) / pitch, np.nan)
    return gradient_window(U, V, step, window)


def levelled(P, u: np.ndarray, du: np.ndarray, mask: np.ndarray, pitch: float, step: float, window: int):
    """(E (3, ny, nx): E_xx, E_yy, E_xy levelled; dE (n_p, 3, ny, nx)) of the FE displacement u
    (n_face, 2) and its sensitivities du (n_p, n_face, 2) at one level."""
    ux, uy, vx, vy = _gradients(P, u, mask, pitch, step, window)
    E = np.stack([ux + 0.5 * (ux * ux + vx * vx), vy + 0.5 * (uy * uy + vy * vy),
                  0.5 * (uy + vx + ux * uy + vx * vy)])
    dE = np.empty((len(du),) + E.shape)
    for j, d in enumerate(du):  # the window is linear in (U, V) for the fixed mask
        dux, duy, dvx, dvy = _gradients(P, d, mask, pitch, step, window)
        dE[j, 0] = (1 + ux) * dux + vx * dvx
        dE[j, 1] = uy * duy + (1 + vy) * dvy
        dE[j, 2] = 0.5 * ((1 + ux) * duy + uy * dux + (1 + vy) * dvx + vx * dvy)
    return E, dE
