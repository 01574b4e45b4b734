"""Point location on a scikit-fem mesh: the element holding a reference point X and its reference
coordinates ξ with X = x(ξ) (the instruments' gauge marks, the snapshot's marks).

Candidates are the elements whose vertex bounding box, widened by ``tol`` times its size, holds X
(a straight-sided element lies inside the convex hull of its vertices, so no holder is missed).
Each candidate's map is inverted: exactly for simplices (affine), by Newton's method
ξ ← ξ + (∂x/∂ξ)⁻¹ (X − x(ξ)) from the centre for hexahedra and quadrilaterals (multilinear), not
clipped to the cell, so a candidate that does not hold X ends with ξ outside it. A candidate
holds X if ξ lies in the reference cell ([0, 1]ᵈ, or the unit simplex ξ ≥ 0, Σξ ≤ 1) to within
``tol``: a mark on a boundary face that misses by round-off (a dumb-bell's face, a few microns
wide) is read where it is, extrapolated by at most ``tol`` of a cell. Of several holders (a mark
on a shared face) the one it lies deepest inside is taken.

scikit-fem's ``element_finder`` does the same job through a k-d tree of element centroids
(importing scipy.spatial: ≈ 0.1 s a run) and, for hexahedra, a split of the whole mesh into
tetrahedra per call (≈ 0.1 s on the 16³ block), which for a non-planar face is not the hexahedron.
"""

from __future__ import annotations

import numpy as np
import skfem

TOL = 1e-6          # in reference coordinates (fraction of a cell)
_NEWTON_TOL = 1e-14  # |Δξ|, reference coordinates
_NEWTON_ITERATIONS = 50


def _simplex(mesh: skfem.Mesh) -> bool:
    return isinstance(mesh, (skfem.MeshTet, skfem.MeshTri))


def _outside(xi: np.ndarray, simplex: bool) -> np.ndarray:
    """How far each ξ (dim, n) lies outside the reference cell (≤ 0 inside), reference units."""
    if simplex:
        return np.maximum(-xi.min(axis=0), xi.sum(axis=0) - 1.0)
    return np.maximum(-xi.min(axis=0), xi.max(axis=0) - 1.0)


def _inverse_map(mapping, x: np.ndarray, cells: np.ndarray, affine: bool) -> np.ndarray:
    """ξ (dim, n) with x(ξ) = x[:, k] in element cells[k]; NaN where Newton does not converge."""
    X = x[:, :, None]
    if affine:
        return mapping.invF(X, tind=cells)[:, :, 0]
    xi = np.full(X.shape, 0.5)
    with np.errstate(all="ignore"):
        for _ in range(_NEWTON_ITERATIONS):
            step = np.einsum("ijkl,jkl->ikl", mapping.invDF(xi, cells), X - mapping.F(xi, cells))
            xi = xi + step
            if np.all(np.abs(step) < _NEWTON_TOL):
                return xi[:, :, 0]
        done = np.all(np.abs(step) < 1e3 * _NEWTON_TOL, axis=(0, 2))
    xi = xi[:, :, 0]
    xi[:, ~done] = np.nan
    return xi


def locate(basis: skfem.CellBasis, points: np.ndarray, tol: float = TOL) -> tuple[np.ndarray, np.ndarray]:
    """(cells (n,), ξ (dim, n)) of ``points`` (dim, n), mm. Raises ValueError naming the first
    point that no element holds."""
    mesh, mapping = basis.mesh, basis.mapping
    points = np.asarray(points, dtype=float)
    simplex, affine = _simplex(mesh), isinstance(mapping, skfem.MappingAffine)
    lo = np.stack([mesh.p[d, mesh.t].min(axis=0) for d in range(mesh.dim())])  # (dim, n_elements)
    hi = np.stack([mesh.p[d, mesh.t].max(axis=0) for d in range(mesh.dim())])
    pad = tol * (hi - lo).max(axis=0)
    cells = np.empty(points.shape[1], dtype=np.int64)
    xi = np.empty(points.shape)
    for k in range(points.shape[1]):
        p = points[:, k:k + 1]
        candidates = np.flatnonzero(np.all((p >= lo - pad) & (p <= hi + pad), axis=0))
        found = None
        if len(candidates):
            ref = _inverse_map(mapping, np.repeat(p, len(candidates), axis=1), candidates, affine)
            out = _outside(ref, simplex)
            best = int(np.nanargmin(out)) if np.isfinite(out).any() else None
            if best is not None and out[best] <= tol:
                found = (candidates[best], ref[:, best])
        if found is None:
            raise ValueError(f"point {points[:, k].tolist()} lies outside the mesh")
        cells[k], xi[:, k] = found
    return cells, xi
