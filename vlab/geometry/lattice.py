"""Structured hexahedral blocks, their tetrahedral split, and mirror images: the meshes of vlab's own
specimen meshers.

A hexahedron is stored by its corners ``c[di, dj, dk]`` (node ids, di, dj, dk ∈ {0, 1}) with di, dj,
dk pointing along increasing x, y, z ("lattice order"), so every block and every mirror image keeps
one orientation and scikit-fem's positive-Jacobian node order follows from a fixed permutation.

Tetrahedra come from the Kuhn (Freudenthal) split of each hexahedron: six tetrahedra along its main
diagonal c[0,0,0]–c[1,1,1], one per ordering of the three axes (0 ≤ ξ_σ1 ≤ ξ_σ2 ≤ ξ_σ3 ≤ 1). The
split is conforming between neighbours in lattice order and invariant under any permutation of the
axes, so a mesh symmetric under x ↔ y stays symmetric once split.

Symmetry: a specimen builds one unit (the part in x ≥ x₀, y ≥ y₀, z ≥ z₀ of its symmetry planes)
and :meth:`Lattice.mirror` reflects it across a plane, merging the nodes on the plane. The full
mesh is the unit mirrored across all three planes, a reduced one across fewer; so a reduced model
is exactly a part of the full mesh (same elements, same split) and their results agree to solver
precision.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import permutations

import numpy as np
import skfem
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

_REF = skfem.MeshHex().p[:, skfem.MeshHex().t[:, 0]].T.astype(int)  # skfem local node -> (di, dj, dk)


@dataclass(frozen=True)
class Lattice:
    """Nodes (n, 3) and cells: hexahedra (e, 2, 2, 2) in lattice order, or tetrahedra (e, 4)."""

    nodes: np.ndarray
    cells: np.ndarray

    @property
    def is_hex(self) -> bool:
        return self.cells.ndim == 4

    @classmethod
    def block(cls, X: np.ndarray) -> "Lattice":
        """A structured block from its node grid X (ni, nj, nk, 3), indices along increasing x, y, z."""
        ni, nj, nk = X.shape[:3]
        ids = np.arange(ni * nj * nk).reshape(ni, nj, nk)
        cells = np.empty((ni - 1, nj - 1, nk - 1, 2, 2, 2), dtype=np.int64)
        for di in (0, 1):
            for dj in (0, 1):
                for dk in (0, 1):
                    cells[..., di, dj, dk] = ids[di:ni - 1 + di, dj:nj - 1 + dj, dk:nk - 1 + dk]
        return cls(X.reshape(-1, 3).astype(float), cells.reshape(-1, 2, 2, 2))

    def join(self, other: "Lattice", tol: float) -> "Lattice":
        """Union of two lattices; nodes closer than ``tol`` are merged."""
        nodes = np.vstack([self.nodes, other.nodes])
        cells = np.concatenate([self.cells, other.cells + len(self.nodes)])
        return Lattice(nodes, cells).merged(tol)

    def mirror(self, axis: int, value: float, tol: float) -> "Lattice":
        """This lattice and its reflection across the plane X[axis] = value (nodes on it merged)."""
        nodes = self.nodes.copy()
        nodes[:, axis] = 2.0 * value - nodes[:, axis]
        cells = np.flip(self.cells, axis=1 + axis) if self.is_hex else self.cells
        return self.join(Lattice(nodes, np.ascontiguousarray(cells)), tol)

    def merged(self, tol: float) -> "Lattice":
        """Coincident nodes (closer than ``tol``) become one; node order is kept otherwise."""
        from scipy.spatial import cKDTree  # ~0.1 s to import: paid only where it is used

        pairs = cKDTree(self.nodes).query_pairs(tol, output_type="ndarray")
        n = len(self.nodes)
        if len(pairs) == 0:
            return self
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        _, label = connected_components(graph, directed=False)
        first = np.full(label.max() + 1, n)
        np.minimum.at(first, label, np.arange(n))  # the lowest node id of each group
        keep = np.unique(first)
        new_id = np.empty(n, dtype=np.int64)
        new_id[keep] = np.arange(len(keep))
        return Lattice(self.nodes[keep], new_id[first[label]][self.cells])

    def without(self, drop: np.ndarray) -> "Lattice":
        """The lattice less the cells where ``drop`` is True, and less the nodes only they used."""
        cells = self.cells[~np.asarray(drop, bool)]
        used = np.unique(cells)
        new_id = np.full(len(self.nodes), -1, dtype=np.int64)
        new_id[used] = np.arange(len(used))
        return Lattice(self.nodes[used], new_id[cells])

    def centroids(self) -> np.ndarray:
        """(e, 3) cell centroids (mean of the corners)."""
        return self.nodes[self.cells.reshape(len(self.cells), -1)].mean(axis=1)

    def tetrahedra(self) -> "Lattice":
        """Kuhn split: six tetrahedra per hexahedron (module docstring)."""
        if not self.is_hex:
            return self
        tets = []
        for order in permutations(range(3)):
            corner = [0, 0, 0]
            verts = [self.cells[:, 0, 0, 0]]
            for axis in order:
                corner[axis] = 1
                verts.append(self.cells[:, corner[0], corner[1], corner[2]])
            tets.append(np.stack(verts, axis=1))
        return Lattice(self.nodes, np.concatenate(tets))

    def swept(self) -> "Lattice":
        """The same lattice numbered along its longest extent (``sweep``)."""
        return Lattice(*sweep(self.nodes, self.cells))

    def to_mesh(self, cell: str) -> skfem.Mesh:
        """scikit-fem MeshHex (``cell = "hex"``) or MeshTet, numbered by ``swept``."""
        if cell == "hex":
            lattice = self.swept()
            t = lattice.cells[:, _REF[:, 0], _REF[:, 1], _REF[:, 2]]
            return skfem.MeshHex(np.ascontiguousarray(lattice.nodes.T), np.ascontiguousarray(t.T))
        lattice = self.tetrahedra().swept()
        return skfem.MeshTet(np.ascontiguousarray(lattice.nodes.T),
                             np.ascontiguousarray(lattice.cells.T))


def sweep(nodes: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (n, 3) and cells (e, ...) of node ids renumbered along the longest extent: nodes
    and cells (by centroid) sorted by coordinate, the longest axis slowest, the shortest fastest.

    Why: the tangent assembly adds every element's node blocks into the rows of its nodes; in
    this order consecutive elements share most of their nodes and the rows in use at any time
    are those of one cross-section, which stay in cache (ISO 527-2 1BA dogbone, 5,120
    hexahedra: 6.7 → 5.7 ms per kernel call), and equal runs of consecutive elements are slabs
    that threads can assemble side by side (vlab.fe.compiled.slabs)."""
    extent = np.ptp(nodes, axis=0)
    axes = np.argsort(extent, kind="stable")  # shortest first: np.lexsort's fastest key
    tick = 1e-9 * max(float(extent.max()), 1e-300)

    def order(points):
        return np.lexsort(tuple(np.round(points[:, a] / tick) for a in axes))

    node_order = order(nodes)
    new_id = np.empty(len(nodes), dtype=np.int64)
    new_id[node_order] = np.arange(len(nodes))
    renumbered = new_id[cells]
    centroids = nodes[cells.reshape(len(cells), -1)].mean(axis=1)
    return nodes[node_order], renumbered[order(centroids)]


def swept_mesh(mesh: skfem.Mesh) -> skfem.Mesh:
    """A scikit-fem mesh without named boundaries or subdomains, numbered by ``sweep``."""
    nodes, cells = sweep(mesh.p.T, mesh.t.T)
    return type(mesh)(np.ascontiguousarray(nodes.T), np.ascontiguousarray(cells.T))


def symmetric_mesh(unit: Lattice, planes: list[tuple[int, float]], cell: str, scale: float) -> skfem.Mesh:
    """The unit split (tets) first, then mirrored across ``planes`` [(axis, value)]: the mirror
    images of a split unit, so the full and every reduced mesh share their elements."""
    tol = 1e-9 * scale
    lattice = unit if cell == "hex" else unit.tetrahedra()
    for axis, value in planes:
        lattice = lattice.mirror(axis, value, tol)
    return lattice.to_mesh(cell)


def divisions(length: float, size: float) -> int:
    """Number of elements of edge ≤ ``size`` over ``length`` (at least one)."""
    return max(1, int(np.ceil(length / size - 1e-9)))
