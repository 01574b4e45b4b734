"""Symmetry reduction: which planes a scene's ``[mesh] symmetry`` cuts, and how the lab's readings
of the full specimen are taken on the kept part.

Levels: "none"; "half" cuts the plane normal to x through the specimen centre; "quarter" adds the
plane normal to y; "eighth" adds the mid-plane of the thickness (normal to z). The kept part is
X[axis] ≥ centre[axis] for each cut plane. On a cut plane the normal displacement is zero (the
full solution is symmetric, so the plane stays plane and in place).

Readings:
- force: the kept grip carries 1/2 of the full force for each plane parallel to its axis (the
  plane halves its section), all of it for a plane normal to its axis (Specimen.force_factor);
- gauge marks outside the kept part are read at their mirror image P' = R P and reflected back,
  x = R x', with R the reflection across the cut planes the mark lies behind; the distances the
  extensometers read are then the full specimen's;
- areas, grip separations and gauge lengths stay the full specimen's.
"""

from __future__ import annotations

import numpy as np

SYMMETRY_LEVELS = ("none", "half", "quarter", "eighth")
_AXES = {"none": (), "half": (0,), "quarter": (0, 1), "eighth": (0, 1, 2)}


def cut_axes(level: str) -> tuple[int, ...]:
    """The axes whose mid-planes a symmetry level cuts."""
    return _AXES[level]


def mirrored_planes(level: str) -> tuple[int, ...]:
    """The axes a specimen's unit (one octant) is mirrored across to build the mesh of ``level``."""
    return tuple(a for a in range(3) if a not in _AXES[level])


def reflection(point, planes: tuple[tuple[int, float], ...]) -> tuple[np.ndarray, np.ndarray]:
    """(P', signs): the image of ``point`` in the kept part and the per-axis sign of the reflection
    (−1 across each cut plane the point lies behind). x = centre + signs · (x' − centre) per axis."""
    image = np.array(point, dtype=float)
    signs = np.ones(3)
    for axis, value in planes:
        if image[axis] < value:
            image[axis] = 2.0 * value - image[axis]
            signs[axis] = -1.0
    return image, signs


def reflect_back(x_image: np.ndarray, signs: np.ndarray, planes: tuple[tuple[int, float], ...]) -> np.ndarray:
    """The deformed position of the original point from that of its image (inverse of reflection)."""
    x = np.array(x_image, dtype=float)
    for axis, value in planes:
        if signs[axis] < 0:
            x[axis] = 2.0 * value - x[axis]
    return x
