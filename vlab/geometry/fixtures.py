"""Rigid fixtures of a test drawn beside the specimen (not meshed, not solved): a confined-compression
die and its platens, a shear test's plates. Each is a triangulated surface in the reference
configuration that either stays where it is (a die's wall) or moves rigidly by the mean
displacement of the specimen vertices it is bonded to (a platen on an end face, a plate on a layer).

The surfaces are built here with numpy (no pyvista), so a Snapshot carries them across processes:
- ``box(lo, hi)``: the 12 triangles of an axis-aligned box;
- ``tube(x0, x1, centre, radius)``: the open lateral surface of a cylinder along x, ``SEGMENTS``
  facets round; ``square_tube(lo, hi)`` the four faces of a box normal to y and z (a block's die);
- ``disc(x0, x1, centre, radius)``: a closed cylinder along x (a platen), the tube and two caps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SEGMENTS = 48  # facets round a tube: the chord's sagitta is 1 − cos(π/48) = 2e-3 of the radius
DIE_COLOUR, PLATEN_COLOUR, PLATE_COLOUR = "#7fa7c9", "#8c8c8c", "#a6a6a6"


@dataclass(frozen=True)
class Fixture:
    """``points`` (n, 3) reference vertices (mm) and ``triangles`` (m, 3) of the surface;
    ``displacement`` (n_frames, 3) its rigid translation per frame (mm); drawn in ``colour`` at
    ``opacity`` (1: opaque; a die's wall is see-through, so the specimen inside shows)."""

    name: str
    points: np.ndarray
    triangles: np.ndarray
    displacement: np.ndarray
    colour: str = PLATE_COLOUR
    opacity: float = 1.0

    def at(self, frame: int) -> np.ndarray:
        """(n, 3) vertex positions at ``frame``, mm."""
        return self.points + self.displacement[frame]


@dataclass(frozen=True)
class Part:
    """A fixture before the run is known: its surface and the selector (reference positions
    (k, 3) -> bool (k,)) of the specimen vertices it is bonded to, or None (it stays)."""

    name: str
    points: np.ndarray
    triangles: np.ndarray
    bonded: object = None
    colour: str = PLATE_COLOUR
    opacity: float = 1.0

    def placed(self, X: np.ndarray, u: np.ndarray) -> Fixture:
        """The fixture moved by the mean displacement of the vertices ``bonded`` selects among
        ``X`` (n_vertices, 3), ``u`` (n_frames, n_vertices, 3) the vertices' displacements."""
        if self.bonded is None:
            move = np.zeros((u.shape[0], 3))
        else:
            on = np.asarray(self.bonded(X), dtype=bool)
            if not on.any():
                raise ValueError(f"fixture {self.name!r} is bonded to no vertex of the mesh")
            move = u[:, on].mean(axis=1)
        return Fixture(self.name, self.points, self.triangles, move, self.colour, self.opacity)


_BOX_FACES = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def _quads(faces) -> np.ndarray:
    return np.array([t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))], dtype=np.int64)


def _corners(lo, hi) -> np.ndarray:
    """The 8 corners, index = 4 i_x + 2 i_y + i_z (0: lo, 1: hi on that axis)."""
    return np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]]
                     for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=float)


def box(lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """(points, triangles) of the box ``lo``..``hi`` (mm)."""
    return _corners(lo, hi), _quads(_BOX_FACES)


def square_tube(lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """(points, triangles) of the box's four faces normal to y and z: open at both x ends."""
    return _corners(lo, hi), _quads(_BOX_FACES[2:])


def tube(x0: float, x1: float, centre, radius: float, segments: int = SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """(points, triangles) of the lateral surface r = ``radius`` about the x-parallel axis through
    ``centre`` (y, z), from x0 to x1: ring k at angle 2πk/``segments`` has vertices k (x0), k + n (x1)."""
    angle = 2.0 * np.pi * np.arange(segments) / segments
    ring = np.column_stack([centre[0] + radius * np.cos(angle), centre[1] + radius * np.sin(angle)])
    points = np.vstack([np.column_stack([np.full(segments, x), ring]) for x in (x0, x1)])
    k = np.arange(segments)
    nxt = (k + 1) % segments
    return points, _quads(zip(k, nxt, nxt + segments, k + segments))


def disc(x0: float, x1: float, centre, radius: float, segments: int = SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """(points, triangles) of the closed cylinder: ``tube`` and a fan cap at each end (the caps'
    centres are the last two vertices)."""
    points, triangles = tube(x0, x1, centre, radius, segments)
    n = len(points)
    points = np.vstack([points, [[x0, centre[0], centre[1]], [x1, centre[0], centre[1]]]])
    k = np.arange(segments)
    nxt = (k + 1) % segments
    caps = np.concatenate([np.column_stack([np.full(segments, n), nxt, k]),
                           np.column_stack([np.full(segments, n + 1), k + segments, nxt + segments])])
    return points, np.vstack([triangles, caps]).astype(np.int64)
