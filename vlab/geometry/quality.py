"""Element quality of a tetrahedral or hexahedral mesh (vertices only; 1 is ideal, ≤ 0 inverted).

- Tetrahedra: mean-ratio quality q = 12 (3V)^(2/3) / Σ l²  over the six edges l (q = 1 for the
  regular tetrahedron; a cube split into six tetrahedra gives q ≈ 0.72 for each).
- Hexahedra: scaled Jacobian q = min over the eight corners of det[e₁, e₂, e₃] with eᵢ the unit
  edge vectors leaving the corner along the local ξ, η, ζ directions (q = 1 for any box).
- Aspect ratio: longest edge / shortest edge of each element (1 for a cube or regular tet).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from itertools import combinations

import numpy as np
import skfem


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


def _edge_lengths(mesh: skfem.Mesh) -> np.ndarray:
    """(n_elements, n_edges) edge lengths from the mesh's edge table."""
    edges = mesh.p[:, mesh.edges]  # (3, 2, n_edges)
    length = np.linalg.norm(edges[:, 1] - edges[:, 0], axis=0)
    return length[mesh.t2e.T]


def mesh_quality(mesh: skfem.Mesh) -> MeshQuality:
    x = mesh.p.T[mesh.t.T]  # (n_elements, n_vertices, 3)
    hexes = isinstance(mesh, skfem.MeshHex)
    q = _hex_quality(x) if hexes else _tet_quality(x)
    lengths = _edge_lengths(mesh)
    aspect = lengths.max(axis=1) / lengths.min(axis=1)
    worst = int(np.argmin(q))
    return MeshQuality("scaled Jacobian" if hexes else "mean ratio", float(q[worst]),
                       float(np.mean(q)), float(aspect.max()), worst)
