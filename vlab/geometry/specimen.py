"""What every specimen offers the lab: a mesh plus the named places a test needs.

Grips are chosen on reference coordinates, so the same selection works for the vertices of an
order-1 mesh and the extra nodes of an order-2 one. Gauge marks are material points on the
surface, evaluated through the finite-element interpolation, so they need not be mesh nodes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import skfem

Selector = Callable[[np.ndarray], np.ndarray]  # reference coordinates (n, dim) -> bool mask (n,)


@dataclass(frozen=True)
class Grip:
    """A grip pulling along ``axis`` (0 = x, 1 = y) from side -1 (fixed) or +1 (moving)."""

    name: str
    axis: int
    side: int
    select: Selector


@dataclass(frozen=True)
class GaugeMarks:
    """Two material points whose distance an extensometer reads (reference positions, mm)."""

    a: tuple[float, ...]  # (x, y, z); (x, y) on a 2D sheet
    b: tuple[float, ...]

    @property
    def length(self) -> float:
        return float(np.linalg.norm(np.subtract(self.b, self.a)))


@dataclass(frozen=True)
class Plate:
    """A rigid part bonded to the specimen that the renders draw (not meshed): the box ``lo``..``hi``
    (reference corners, mm), moved rigidly by the mean displacement of the mesh vertices on its
    surface (within 1e−9 of the specimen's length scale)."""

    lo: tuple[float, float, float]
    hi: tuple[float, float, float]


@dataclass(frozen=True)
class View:
    """How a lab photographs the specimen for its test: ``direction`` from the specimen to the camera
    and the screen's ``up`` (unit vectors need not be given normalised), and the rigid ``plates`` in
    the picture. A specimen without one is seen from the renders' default direction
    (vlab.render.camera.VIEW_DIRECTION)."""

    direction: tuple[float, float, float]
    up: tuple[float, float, float]
    plates: tuple[Plate, ...] = ()


@dataclass(frozen=True)
class Specimen:
    """A meshed specimen.

    ``grip_separation[axis]`` is the initial distance between the two grips on that axis (mm);
    ``extensometers[axis]`` the axial gauge marks; ``transverse[axis]`` the marks across the
    width at the gauge centre for a test loaded along ``axis``; ``thickness`` the marks through
    the thickness at the gauge centre; ``area0[axis]`` the gauge-section area normal to the axis;
    ``regions`` named selectors (reference coordinates) such as "gauge" and "fillets" that the
    homogeneity measurement reads; ``sheet_thickness`` the thickness of a 2D (plane) specimen,
    whose ``thickness`` marks are the two faces (z = 0 and z = t) over an in-plane point.

    ``centred``: both grips of an axis move, by ±Δ/2 (a biaxial machine's four actuators keep the
    specimen centre in place); otherwise the side −1 grip holds and the side +1 grip moves by Δ.
    ``symmetry``: the planes (axis, value) of a reduced model; the mesh is the part X[axis] ≥ value
    of the full specimen, every other field (marks, areas, grip separation) is the full specimen's.
    ``view``: how the renders look at it (a :class:`View`), None for the default direction.
    """

    shape: str
    mesh: skfem.Mesh
    grips: tuple[Grip, ...]
    grip_separation: dict[int, float]
    extensometers: dict[int, GaugeMarks]
    transverse: dict[int, GaugeMarks]
    thickness: GaugeMarks
    area0: dict[int, float]
    length_scale: float
    regions: dict[str, Selector] = field(default_factory=dict)
    sheet_thickness: float | None = None  # mm, for a 2D sheet (its mesh is in the x-y plane)
    centred: bool = False
    symmetry: tuple[tuple[int, float], ...] = ()
    view: View | None = None  # the renders' camera and rigid plates (None: the default view)

    def grips_on(self, axis: int) -> tuple[Grip, ...]:
        """The (fixed, moving) grips of an axis; only the moving one when a symmetry plane normal to
        the axis has cut the fixed one away."""
        moving = next(g for g in self.grips if g.axis == axis and g.side > 0)
        fixed = [g for g in self.grips if g.axis == axis and g.side < 0]
        return (*fixed, moving)

    def reduced(self, axis: int) -> bool:
        """True if a symmetry plane normal to ``axis`` cuts the specimen."""
        return any(a == axis for a, _ in self.symmetry)

    def force_factor(self, axis: int) -> float:
        """Full-specimen force / force on the kept part's grip along ``axis``: each symmetry plane
        parallel to the axis halves the grip's section, a plane normal to it leaves it whole."""
        return float(2 ** sum(1 for a, _ in self.symmetry if a != axis))


@dataclass(frozen=True)
class SizedSpec:
    """A specimen spec given by ``size`` (mm), loaded along its first dimension (x)."""

    @property
    def length(self) -> float:
        return self.size[0]  # type: ignore[attr-defined]

    @property
    def max_dimension(self) -> float:
        return max(self.size)  # type: ignore[attr-defined]
