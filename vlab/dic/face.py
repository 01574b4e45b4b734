"""A flat face of an FE specimen as a 2-D mesh the virtual camera looks at (vlab.dic.camera).

The face is the set of boundary facets of a scikit-fem mesh lying in the plane X_axis = value
(within 1e-9 of the mesh size): their nodes, in-plane reference coordinates (mm) and cells, each
listed corners first, counter-clockwise as seen from outside. Without a basis (or with an order-1
one) the cells are the facets' vertices: bilinear quadrilaterals (the faces of hexahedra) or linear
triangles (of tetrahedra). With an order-2 basis they carry its facet nodes too, so the face
interpolates the displacement as the FE space does:

- ElementHex2 (27 nodes): 9-node quadrilaterals, corners, then the mid-edge nodes of edges
  (0,1), (1,2), (2,3), (3,0), then the centre;
- ElementHexS2 (20 nodes): 8-node serendipity quadrilaterals, the same without the centre;
- ElementTetP2 (10 nodes): 6-node triangles, corners, then the mid-edge nodes of (0,1), (1,2), (2,0).

Node indices are the basis's scalar DOFs (vertices first), which index vlab's nodal displacement
(n_nodes, 3). The in-plane axes (e₁, e₂) make (e₁, e₂, n) right-handed with n the outward normal,
so a camera on n's side with e₂ up sees e₁ to the right.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


class FaceError(ValueError):
    """No face where asked (exit 2); the message names the axis, the side and what the mesh has."""


@dataclass(frozen=True)
class Face:
    """nodes: (n,) node indices (mesh vertices, or the basis's scalar DOFs); X: (n, 2) in-plane
    reference coordinates (mm) in the face's axes ``axes`` (e₁, e₂ as (mesh axis, sign)); cells:
    (m, k) indices into ``nodes``, k = 3 or 6 (triangles), 4, 8 or 9 (quadrilaterals), corners
    counter-clockwise in (e₁, e₂) first (the module docstring gives the order)."""

    nodes: np.ndarray
    X: np.ndarray
    cells: np.ndarray
    axes: tuple[tuple[int, int], tuple[int, int]]

    def in_plane(self, u: np.ndarray) -> np.ndarray:
        """The in-plane displacement (n, 2) mm of the face's nodes from the nodal displacement
        ``u`` (n_vertices or more, 3) of the mesh (the vertices come first, as in vlab's spaces; a face
        built with a basis needs all the basis's nodes)."""
        u = np.asarray(u, float)[self.nodes]
        return np.stack([sign * u[:, axis] for axis, sign in self.axes], axis=1)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(lo (2,), hi (2,)) of the reference face, mm."""
        return self.X.min(axis=0), self.X.max(axis=0)


def _axes(axis: int, side: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """(e₁, e₂) with (e₁, e₂, side·e_axis) right-handed: e₁ = side·e_{axis+1}, e₂ = e_{axis+2}."""
    return ((axis + 1) % 3, side), ((axis + 2) % 3, 1)


def face_of(mesh, axis: int = 2, side: int = 1, basis=None) -> Face:
    """The face of ``mesh`` (3-D skfem mesh) on the plane X_axis = max (side +1) or min (side −1),
    with the outward normal side·e_axis; with ``basis`` (a scalar skfem basis on ``mesh``, e.g. a
    DisplacementSpace's) its cells carry the basis's facet nodes. FaceError if no boundary facet
    lies in that plane."""
    if axis not in (0, 1, 2) or side not in (-1, 1):
        raise FaceError(f"face axis = {axis!r}, side = {side!r}: axis must be 0, 1 or 2 (x, y, z), side ±1")
    p = mesh.p
    if p.shape[0] != 3:
        raise FaceError(f"a face needs a 3-D mesh; this one is {p.shape[0]}-D")
    value = p[axis].max() if side > 0 else p[axis].min()
    tol = 1e-9 * float(np.ptp(p, axis=1).max())
    facets = mesh.facets[:, mesh.boundary_facets()]
    on = np.all(np.abs(p[axis][facets] - value) <= tol, axis=0)
    if not on.any():
        raise FaceError(f"no boundary facet of the mesh lies on X{'xyz'[axis]} = {value:g} mm")
    axes = _axes(axis, side)
    corners = _counter_clockwise(np.stack([sign * p[a] for a, sign in axes], axis=1), facets[:, on].T)
    if basis is None:
        global_cells, points = corners, p
    else:
        global_cells = _quadratic_cells(mesh, basis, corners, mesh.boundary_facets()[on])
        points = basis.doflocs
    nodes, local = np.unique(global_cells, return_inverse=True)
    X = np.stack([sign * points[a][nodes] for a, sign in axes], axis=1)
    return Face(nodes, X, local.reshape(global_cells.shape), axes)


def _quadratic_cells(mesh, basis, corners: np.ndarray, facet_index: np.ndarray) -> np.ndarray:
    """(m, k) scalar DOFs of the face cells in ``basis``: the corners' nodal DOFs, then (order 2)
    one DOF per edge of consecutive corners, then (9-node quadrilaterals) the facet's own DOF."""
    elem = basis.elem
    centre = int(elem.edge_dofs == 1 and corners.shape[1] == 4)  # a quadratic quadrilateral may have one
    if elem.nodal_dofs != 1 or elem.edge_dofs not in (0, 1) or elem.facet_dofs not in (0, centre):
        raise FaceError(f"a face of a {type(elem).__name__} space: the camera takes Lagrange spaces of "
                        f"order 1 or 2 (one DOF per vertex, per edge, and per quadrilateral facet at most)")
    cells = [basis.nodal_dofs[0][corners]]
    if elem.edge_dofs:
        n = mesh.p.shape[1]
        keys = np.sort(mesh.edges, axis=0)
        keys = keys[0] * n + keys[1]
        order = np.argsort(keys)
        a, b = corners, np.roll(corners, -1, axis=1)
        want = np.minimum(a, b) * n + np.maximum(a, b)
        cells.append(basis.edge_dofs[0][order[np.searchsorted(keys, want, sorter=order)]])
    if elem.facet_dofs:
        cells.append(basis.facet_dofs[0][facet_index][:, None])
    return np.concatenate(cells, axis=1)


def _counter_clockwise(X: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Each cell's vertices (indices into X) sorted by angle about its centroid (scikit-fem stores
    a facet's vertices sorted by index, not around the facet; a flat convex facet is ordered by
    angle)."""
    centre = X[cells].mean(axis=1, keepdims=True)
    d = X[cells] - centre
    order = np.argsort(np.arctan2(d[..., 1], d[..., 0]), axis=1)
    return np.take_along_axis(cells, order, axis=1)
