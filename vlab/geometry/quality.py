"""Element quality of a tetrahedral, hexahedral, triangular or quadrilateral mesh (vertices only; 1 is ideal, ≤ 0 inverted).

- Tetrahedra: mean-ratio quality q = 12 (3V)^(2/3) / Σ l²  over the six edges l (q = 1 for the
  regular tetrahedron; a cube split into six tetrahedra gives q ≈ 0.72 for each).
- Hexahedra: scaled Jacobian q = min over the eight corners of det[e₁, e₂, e₃] with eᵢ the unit
  edge vectors leaving the corner along the local ξ, η, ζ directions (q = 1 for any box).
- Triangles: mean ratio 4√3 A / Σ l² (1 for the equilateral triangle, ≈ 0.87 for a square split
  in two); quadrilaterals: the scaled Jacobian over the four corners (1 for any rectangle).
- Aspect ratio: longest edge / shortest edge of each element (1 for a cube or regular tet).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from itertools import combinations

import numpy as np
import skfem

from vlab.geometry.mesh_check import quad_scaled_jacobian


@dataclass(frozen=True)
class MeshQuality:
    measure: str  # "mean ratio" (tets) or "scaled Jacobian" (hexes)
    min_quality: float
    mean_quality: float
    max_aspect_ratio: float
    worst_element: int

    def as_dict(self) -> dict:
        return asdict(self)


def _hex_corner_neighbours() -> list[list[tuple[int, int]]]:
    """For each corner of scikit-fem's reference hex: (neighbour, +1/−1) along ξ, η, ζ."""
    ref = skfem.MeshHex().p.T[skfem.MeshHex().t[:, 0]]
    out = []
    for corner in ref:
        row = []
        for axis in range(3):
            target = corner.copy()
            target[axis] = 1.0 - target[axis]
            nbr = int(np.flatnonzero(np.all(ref == target, axis=1))[0])
            row.append((nbr, 1 if target[axis] > corner[axis] else -1))
        out.append(row)
    return out


def _hex_quality(x: np.ndarray) -> np.ndarray:
    """x: (n_elements, 8, 3) corner coordinates -> scaled Jacobian (n_elements,)."""
    q = np.full(len(x), np.inf)
    for c, nbrs in enumerate(_hex_corner_neighbours()):
        e = np.stack([sign * (x[:, n] - x[:, c]) for n, sign in nbrs], axis=-1)  # (n, 3, 3)
        e = e / np.linalg.norm(e, axis=1, keepdims=True)
        q = np.minimum(q, np.linalg.det(e))
    return q


def _tet_quality(x: np.ndarray) -> np.ndarray:
    """x: (n_elements, 4, 3) -> mean ratio (n_elements,), 0 for a flat tet. Vertex order (and so
    the sign of the volume) is a numbering convention the solver does not depend on."""
    V = np.linalg.det(np.stack([x[:, k] - x[:, 0] for k in (1, 2, 3)], axis=-1)) / 6.0
    l2 = sum(np.sum((x[:, a] - x[:, b]) ** 2, axis=1) for a, b in combinations(range(4), 2))
    return 12.0 * np.cbrt(3.0 * np.abs(V)) ** 2 / l2


def _tri_quality(x: np.ndarray) -> np.ndarray:
    """x: (n_elements, 3, 2) -> mean ratio 4√3 A / Σ l² (1 for the equilateral triangle)."""
    d1, d2 = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    area = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    l2 = sum(np.sum((x[:, a] - x[:, b]) ** 2, axis=1) for a, b in combinations(range(3), 2))
    return 4.0 * np.sqrt(3.0) * area / l2


def _edge_lengths(mesh: skfem.Mesh) -> np.ndarray:
    """(n_elements, n_edges) edge lengths from the mesh's edge table (facets in 2D)."""
    table, t2e = (mesh.facets, mesh.t2f) if mesh.dim() == 2 else (mesh.edges, mesh.t2e)
    edges = mesh.p[:, table]  # (dim, 2, n_edges)
    length = np.linalg.norm(edges[:, 1] - edges[:, 0], axis=0)
    return length[t2e.T]


def _quality(mesh: skfem.Mesh, x: np.ndarray) -> tuple[str, np.ndarray]:
    if isinstance(mesh, skfem.MeshHex):
        return "scaled Jacobian", _hex_quality(x)
    if isinstance(mesh, skfem.MeshQuad):
        return "scaled Jacobian", quad_scaled_jacobian(x.transpose(2, 1, 0))
    if isinstance(mesh, skfem.MeshTri):
        return "mean ratio", _tri_quality(x)
    return "mean ratio", _tet_quality(x)


def mesh_quality(mesh: skfem.Mesh) -> MeshQuality:
    x = mesh.p.T[mesh.t.T]  # (n_elements, n_vertices, dim)
    measure, q = _quality(mesh, x)
    lengths = _edge_lengths(mesh)
    aspect = lengths.max(axis=1) / lengths.min(axis=1)
    worst = int(np.argmin(q))
    return MeshQuality(measure, float(q[worst]),
                       float(np.mean(q)), float(aspect.max()), worst)
