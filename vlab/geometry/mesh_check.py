"""Checks a specimen mesh before any solve: a bad mesh is a clear error, not a bad number.

- inverted or degenerate elements: det J ≤ 0 of the reference map at any corner (hexahedra);
  |det J| ≈ 0 for tetrahedra (affine maps, which scikit-fem accepts in either orientation);
- duplicate nodes (two vertices closer than ``1e-9`` × the mesh extent: a crack in disguise) and
  unused nodes (vertices no element refers to: DOFs without stiffness);
- 2D sheets: the same measures in the plane (triangle_flatness, quad_scaled_jacobian);
- slivers: a flatness measure q below ``MIN_QUALITY``. Hexahedra: the scaled Jacobian
      q = min over corners c of  det[e₁ e₂ e₃] / (|e₁| |e₂| |e₃|)
  (e_i the edges leaving corner c; 1 for right-angled corners). Tetrahedra: the smallest height
  over the shortest edge, q = (h_min / l_min) / √(2/3) (1 for a regular tetrahedron). Both
  measure flatness, not size or aspect: a 10:1 brick, or the needle tetrahedra it splits into,
  stay well above the threshold, so valid high-aspect-ratio meshes pass; flattened elements whose
  corners are nearly coplanar do not.
"""

from __future__ import annotations

import numpy as np
import skfem

MIN_QUALITY = 0.05
DUPLICATE_TOL = 1e-9

DEGENERATE = 1e-12


class MeshError(ValueError):
    """The mesh cannot be solved on; the message names the elements or nodes."""


def element_quality(mesh: skfem.Mesh) -> np.ndarray:
    """Scaled Jacobian q per element (≤ 0: inverted or degenerate; 1: ideal corners)."""
    p, t = mesh.p, mesh.t
    if isinstance(mesh, skfem.MeshTet):
        return _tet_flatness(p[:, t])
    if isinstance(mesh, skfem.MeshHex):
        return np.min([_scaled_det(*e) for e in _hex_corner_edges(mesh)], axis=0)
    if isinstance(mesh, skfem.MeshTri):
        return triangle_flatness(p[:, t])
    if isinstance(mesh, skfem.MeshQuad):
        return quad_scaled_jacobian(p[:, t])
    raise MeshError(f"mesh type {type(mesh).__name__} is not supported (tetrahedra, hexahedra, "
                    f"triangles or quadrilaterals)")


def triangle_flatness(X: np.ndarray) -> np.ndarray:
    """Triangles X (2, 3, e): q = (smallest height / shortest edge) / (√3/2), 1 for an equilateral
    triangle, → 0 as the corners become collinear (the 2D analogue of the tetrahedra's measure)."""
    a, b, c = (X[:, k] for k in range(3))
    area2 = np.abs((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0])
    edges = np.stack([np.linalg.norm(b - a, axis=0), np.linalg.norm(c - b, axis=0),
                      np.linalg.norm(a - c, axis=0)])
    longest, shortest = edges.max(axis=0), edges.min(axis=0)
    height = area2 / np.where(longest > 0, longest, 1.0)
    return np.where(shortest > 0, height / np.where(shortest > 0, shortest, 1.0), 0.0) / (np.sqrt(3) / 2)


def quad_scaled_jacobian(X: np.ndarray) -> np.ndarray:
    """Quadrilaterals X (2, 4, e), corners in cyclic order: q = min over corners of
    (e₁ × e₂)/(|e₁||e₂|), signed by the element's orientation (its shoelace area), so 1 for a
    rectangle in either winding and ≤ 0 for a folded (bow-tie) or flat element."""
    x, y = X[0], X[1]
    orientation = np.sign(np.sum(x * np.roll(y, -1, axis=0) - np.roll(x, -1, axis=0) * y, axis=0))
    q = np.full(X.shape[2], np.inf)
    for k in range(4):
        e1, e2 = X[:, (k + 1) % 4] - X[:, k], X[:, (k - 1) % 4] - X[:, k]
        cross = e1[0] * e2[1] - e1[1] * e2[0]
        norms = np.linalg.norm(e1, axis=0) * np.linalg.norm(e2, axis=0)
        q = np.minimum(q, np.where(norms > 0, orientation * cross / np.where(norms > 0, norms, 1.0), 0.0))
    return q


def _tet_flatness(X: np.ndarray) -> np.ndarray:
    """q = (smallest height / shortest edge) / √(2/3) for tetrahedra X (3, 4, e): 1 for a regular
    tetrahedron, → 0 when the four corners become coplanar, but not small for a long needle."""
    a, b, c, d = (X[:, k] for k in range(4))
    volume6 = np.abs(np.einsum("ie,ie->e", b - a, np.cross(c - a, d - a, axis=0)))
    faces = ((b, c, d), (a, c, d), (a, b, d), (a, b, c))
    area2 = np.max([np.linalg.norm(np.cross(v - u, w - u, axis=0), axis=0) for u, v, w in faces], axis=0)
    edges = [np.linalg.norm(X[:, i] - X[:, j], axis=0) for i in range(4) for j in range(i + 1, 4)]
    shortest = np.min(edges, axis=0)
    height = volume6 / np.where(area2 > 0, area2, 1.0)  # 3V / A = 6V / (2A), largest face
    return np.where(shortest > 0, height / np.where(shortest > 0, shortest, 1.0), 0.0) / np.sqrt(2.0 / 3.0)


def _scaled_det(e1: np.ndarray, e2: np.ndarray, e3: np.ndarray) -> np.ndarray:
    det = np.einsum("ie,ie->e", e1, np.cross(e2, e3, axis=0))
    norms = np.linalg.norm(e1, axis=0) * np.linalg.norm(e2, axis=0) * np.linalg.norm(e3, axis=0)
    return np.where(norms > 0, det / np.where(norms > 0, norms, 1.0), 0.0)


def _hex_corner_edges(mesh: skfem.MeshHex):
    """For each of the 8 corners, the 3 edge vectors (3, n_elements) to its neighbours, ordered
    as the reference axes so that a right-handed element gives a positive determinant."""
    ref = skfem.MeshHex().p.T  # the reference cube's corners in scikit-fem's local order
    index = {tuple(np.round(c).astype(int)): k for k, c in enumerate(ref)}
    X = mesh.p[:, mesh.t]  # (3, 8, e)
    for corner in ref.round().astype(int):
        others = []
        for axis in range(3):
            nb = corner.copy()
            nb[axis] = 1 - nb[axis]
            others.append(index[tuple(nb)])
        k = index[tuple(corner)]
        sign = (-1.0) ** int(corner.sum())  # flipping an odd number of axes mirrors the frame
        e = [X[:, o] - X[:, k] for o in others]
        yield sign * e[0], e[1], e[2]


# a fixed direction with no rational relation between its components: distinct nodes of a
# structured grid do not project onto (nearly) the same value, so the clusters stay pairs
_DIRECTION = np.array([0.5773502691896257, 0.6172133998483676, 0.5345224838248488])


def close_pairs(points: np.ndarray, tol: float) -> np.ndarray:
    """All pairs (i, j), i < j, of rows of ``points`` (n, d) at Euclidean distance ≤ ``tol``,
    sorted; shape (k, 2).

    The rows are sorted by their projection s = x·d on a unit vector d. Two points within ``tol``
    have |s_i − s_j| ≤ tol, and every point between them in that order lies within it too, so
    they fall in one cluster of consecutive projections with gaps ≤ tol; only the pairs inside a
    cluster are measured. Exact, one sort (O(n log n)), no spatial tree: scipy.spatial's cKDTree
    gives the same pairs (tests/test_mesh_check.py) but importing it costs every run ≈ 0.1 s."""
    points = np.asarray(points, float)
    d = _DIRECTION[: points.shape[1]] / np.linalg.norm(_DIRECTION[: points.shape[1]])
    s = points @ d
    order = np.argsort(s, kind="stable")
    close = np.diff(s[order]) <= tol  # close[k]: sorted rows k and k + 1 within tol along d
    if not close.any():
        return np.empty((0, 2), dtype=np.intp)
    starts = np.flatnonzero(close & ~np.r_[False, close[:-1]])  # first gap of each cluster
    ends = np.flatnonzero(close & ~np.r_[close[1:], False]) + 1  # last row of each cluster
    two = ends - starts == 1  # clusters of two rows (the usual case), measured at once
    a, b = order[starts[two]], order[ends[two]]
    within = np.linalg.norm(points[a] - points[b], axis=1) <= tol
    found = [np.sort(np.stack([a[within], b[within]], axis=1), axis=1)]
    for first, last in zip(starts[~two], ends[~two]):
        members = order[first:last + 1]
        for k, i in enumerate(members[:-1]):  # row by row: memory O(cluster), not O(cluster²)
            others = members[k + 1:]
            near = others[np.linalg.norm(points[others] - points[i], axis=1) <= tol]
            found.append(np.sort(np.stack([np.full(len(near), i), near], axis=1), axis=1))
    pairs = np.concatenate(found)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def check_mesh(mesh: skfem.Mesh, min_quality: float = MIN_QUALITY) -> None:
    """Raise MeshError naming the first offending elements or nodes; return None if fine."""
    p, t = mesh.p, mesh.t
    extent = float(np.max(np.ptp(p, axis=1))) or 1.0
    unused = np.setdiff1d(np.arange(p.shape[1]), t.ravel())
    if len(unused):
        raise MeshError(f"mesh has {len(unused)} unused node(s) (no element refers to them), "
                        f"e.g. node(s) {_few(unused)}")
    pairs = close_pairs(p.T, DUPLICATE_TOL * extent)
    if len(pairs):
        raise MeshError(f"mesh has {len(pairs)} pair(s) of duplicate nodes (closer than "
                        f"{DUPLICATE_TOL:g} x extent), e.g. nodes {pairs[0].tolist()}")
    q = element_quality(mesh)
    bad = np.flatnonzero(q <= DEGENERATE)
    if len(bad):
        raise MeshError(f"mesh has {len(bad)} inverted or degenerate element(s) (det J <= 0), "
                        f"e.g. element(s) {_few(bad)} (scaled Jacobian {q[bad[0]]:.3g})")
    bad = np.flatnonzero(q < min_quality)
    if len(bad):
        raise MeshError(f"mesh has {len(bad)} sliver element(s) with scaled Jacobian below "
                        f"{min_quality:g}, e.g. element(s) {_few(bad)} (q = {q[bad].min():.3g})")


def _few(index: np.ndarray, n: int = 5) -> str:
    shown = ", ".join(str(int(i)) for i in index[:n])
    return shown + (", ..." if len(index) > n else "")
