"""A flat face of an FE specimen as a 2-D mesh the virtual camera looks at (vlab.dic.camera).

The face is the set of boundary facets of a scikit-fem mesh lying in the plane X_axis = value
(within 1e-9 of the mesh size): their vertices, in-plane reference coordinates (mm) and cells —
bilinear quadrilaterals (the faces of hexahedra) or linear triangles (of tetrahedra), each listed
counter-clockwise as seen from outside. The in-plane axes (e₁, e₂) make (e₁, e₂, n) right-handed
with n the outward normal, so a camera on n's side with e₂ up sees e₁ to the right.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


class FaceError(ValueError):
    """No face where asked (exit 2); the message names the axis, the side and what the mesh has."""


@dataclass(frozen=True)
class Face:
    """nodes: (n,) mesh vertex indices; X: (n, 2) in-plane reference coordinates (mm) in the face's
    axes ``axes`` (e₁, e₂ as (mesh axis, sign)); cells: (m, 3) triangles or (m, 4) quadrilaterals
    (indices into ``nodes``), counter-clockwise in (e₁, e₂)."""

    nodes: np.ndarray
    X: np.ndarray
    cells: np.ndarray
    axes: tuple[tuple[int, int], tuple[int, int]]

    def in_plane(self, u: np.ndarray) -> np.ndarray:
        """The in-plane displacement (n, 2) mm of the face's nodes from the nodal displacement
        ``u`` (n_vertices or more, 3) of the mesh (the vertices come first, as in vlab's spaces)."""
        u = np.asarray(u, float)[self.nodes]
        return np.stack([sign * u[:, axis] for axis, sign in self.axes], axis=1)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(lo (2,), hi (2,)) of the reference face, mm."""
        return self.X.min(axis=0), self.X.max(axis=0)


def _axes(axis: int, side: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """(e₁, e₂) with (e₁, e₂, side·e_axis) right-handed: e₁ = side·e_{axis+1}, e₂ = e_{axis+2}."""
    return ((axis + 1) % 3, side), ((axis + 2) % 3, 1)


def face_of(mesh, axis: int = 2, side: int = 1) -> Face:
    """The face of ``mesh`` (3-D skfem mesh) on the plane X_axis = max (side +1) or min (side −1),
    with the outward normal side·e_axis. FaceError if no boundary facet lies in that plane."""
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
    facets = facets[:, on].T
    nodes, local = np.unique(facets, return_inverse=True)
    axes = _axes(axis, side)
    X = np.stack([sign * p[a][nodes] for a, sign in axes], axis=1)
    cells = _counter_clockwise(X, local.reshape(facets.shape))
    return Face(nodes, X, cells, axes)


def _counter_clockwise(X: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Each cell's vertices sorted by angle about its centroid (scikit-fem stores a facet's
    vertices sorted by index, not around the facet; a flat convex facet is ordered by angle)."""
    centre = X[cells].mean(axis=1, keepdims=True)
    d = X[cells] - centre
    order = np.argsort(np.arctan2(d[..., 1], d[..., 0]), axis=1)
    return np.take_along_axis(cells, order, axis=1)
