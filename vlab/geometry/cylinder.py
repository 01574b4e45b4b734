"""Solid circular cylinder: ``radius`` a and ``length`` L (mm), its axis along x from x = 0 to L.

Meshed with hexahedra by an O-grid of the cross-section (the y–z disc): a central square of
half-side a/2 and four ring blocks between its edges and the circle, each with n_c divisions along
its quarter of the circumference (n_c even, so nodes sit at the four axis directions, where the
gauge marks are) and n_r radial divisions, swept over n_x divisions along x:

    n_c = 2 ceil(π a / (4 h)),  n_r = ceil(a / (2 h)),  n_x = ceil(L / h)   (h = mesh.size)

elements (n_c² + 4 n_c n_r) n_x. Every boundary node of the ring blocks lies on the circle r = a,
so the facetted surface is inscribed (its area is short of π a² by O((π/(2 n_c))²)). The ring
blocks have one corner cell angle of 135° at the square's corners; none is flat.

Tetrahedra (``mesh.cell = "tet"``): each hexahedron split into six by the smallest-index rule of
vlab.geometry.hex_split (the Kuhn split of blocks in different lattice orders would not conform
across the square's edges); the same nodes, 6 (n_c² + 4 n_c n_r) n_x elements.

The load cells' reference area is the meshed section's (``section_area``): the FE integrates
the traction over the facetted section, so dividing by π a² would bias every stress by
−π²/(24 n_c²) (−0.6 % at n_c = 8) against the homogeneous oracle.

Named places: the grips are the end faces x = 0 (side −1) and x = L (side +1); the region
"lateral" selects the curved surface r = a; the extensometer marks sit on the surface at
(L/2 ∓ g/2, 0, a), the width marks across the diameter along y, the thickness marks along z.

The renders see it from the side as a lab photographs a torsion or compression specimen: the axis
horizontal, the view direction (0.3, −1, 0.35) (a little from the end x = L and above, so the
end face's section and the extensometer marks on top show).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.counts import MeshCount, div
from vlab.geometry.lattice import Lattice
from vlab.geometry.shape import Shape
from vlab.geometry.specimen import GaugeMarks, Grip, Specimen, View

__all__ = ["CylinderSpecimen", "cylinder_divisions", "cylinder_mesh", "cylinder_specimen", "SHAPE"]

INNER = 0.5  # half-side of the O-grid's central square / radius


@dataclass(frozen=True)
class CylinderSpecimen:
    shape: str
    radius: float  # mm
    length: float  # mm, along x (the axis)

    @property
    def max_dimension(self) -> float:
        return max(2.0 * self.radius, self.length)


def parse_cylinder(t: fields.Table) -> CylinderSpecimen:
    radius = t.number("radius", gt=0, note=" (mm)")
    length = t.number("length", gt=0, note=" (mm, along the axis x)")
    return CylinderSpecimen(shape="cylinder", radius=radius, length=length)


def cylinder_divisions(radius: float, length: float, size: float) -> tuple[int, int, int]:
    """(n_c, n_r, n_x) of the module docstring."""
    n_c = 2 * div(math.pi * radius / 4.0, size)
    return n_c, div(radius / 2.0, size), div(length, size)


def _section_blocks(a: float, n_c: int, n_r: int) -> list[np.ndarray]:
    """The O-grid's five blocks as node grids (nj, nk, 2) in the y–z plane."""
    c = INNER * a
    s = np.linspace(-c, c, n_c + 1)
    centre = np.stack(np.meshgrid(s, s, indexing="ij"), axis=-1)
    blocks = [centre]
    w = np.linspace(0.0, 1.0, n_r + 1)
    for quarter in range(4):
        phi = quarter * math.pi / 2  # the block around the direction φ (0: +y, π/2: +z, ...)
        theta = phi + np.linspace(-math.pi / 4, math.pi / 4, n_c + 1)
        rot = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
        inner = (rot @ np.stack([np.full(n_c + 1, c), s]))  # the square's edge facing φ
        outer = a * np.stack([np.cos(theta), np.sin(theta)])
        grid = inner.T[:, None, :] + w[None, :, None] * (outer - inner).T[:, None, :]
        blocks.append(grid)
    return blocks


def cylinder_mesh(radius: float, length: float, size: float):
    """The hexahedral MeshHex of the module docstring."""
    n_c, n_r, n_x = cylinder_divisions(radius, length, size)
    x = np.linspace(0.0, length, n_x + 1)
    lattice = None
    tol = 1e-9 * max(radius, length)
    for block in _section_blocks(radius, n_c, n_r):
        X = np.empty((n_x + 1, *block.shape[:2], 3))
        X[..., 0] = x[:, None, None]
        X[..., 1:] = block[None]
        # lattice order must be right-handed (positive Jacobian): flip the block's first
        # in-plane index where (e_x, e_j, e_k) is left-handed
        d1, d2 = block[1, 0] - block[0, 0], block[0, 1] - block[0, 0]
        if d1[0] * d2[1] - d1[1] * d2[0] < 0:
            X = X[:, ::-1]
        part = Lattice.block(np.ascontiguousarray(X))
        lattice = part if lattice is None else lattice.join(part, tol)
    return lattice.to_mesh("hex")


def cylinder_specimen(spec: CylinderSpecimen, element_size: float, cell: str,
                      gauge_length: float | None = None) -> Specimen:
    a, L = spec.radius, spec.length
    mesh = cylinder_mesh(a, L, element_size)
    if cell == "tet":
        from vlab.geometry.hex_split import swept_hex_to_tets

        mesh = swept_hex_to_tets(mesh)
    elif cell != "hex":
        raise SceneError(f"mesh.cell must be 'hex' or 'tet' for specimen.shape = 'cylinder', got {cell!r}")
    tol = 1e-9 * max(a, L)
    g = gauge_length or L / 2
    if g > L:
        raise SceneError(f"measure.gauge_length must be <= specimen.length = {L:g} mm, got {g:g}")
    return Specimen(
        shape="cylinder",
        mesh=mesh,
        grips=(Grip("x-", 0, -1, lambda X: np.abs(X[:, 0]) <= tol),
               Grip("x+", 0, +1, lambda X: np.abs(X[:, 0] - L) <= tol)),
        grip_separation={0: L},
        extensometers={0: GaugeMarks((L / 2 - g / 2, 0.0, a), (L / 2 + g / 2, 0.0, a))},
        transverse={0: GaugeMarks((L / 2, -a, 0.0), (L / 2, a, 0.0))},
        thickness=GaugeMarks((L / 2, 0.0, -a), (L / 2, 0.0, a)),
        area0={0: section_area(a, element_size)},
        length_scale=float(math.hypot(2 * a, L)),
        regions={"lateral": lambda X: np.abs(np.hypot(X[:, 1], X[:, 2]) - a) <= 1e-6 * a,
                 "core": lambda c: np.abs(c[:, 0] - L / 2) <= L / 4},
        view=View(direction=(0.3, -1.0, 0.35), up=(0.0, 0.0, 1.0)),
    )


def section_area(radius: float, size: float) -> float:
    """The meshed cross-section's area (mm²): the inscribed 4 n_c-gon, 2 n_c a² sin(π / (2 n_c))
    (the boundary nodes are equally spaced in angle), short of π a² by ≈ π³ a² / (24 n_c²)."""
    n_c = cylinder_divisions(radius, 1.0, size)[0]
    return 2.0 * n_c * radius * radius * math.sin(math.pi / (2 * n_c))


def count_cylinder(spec, mesh) -> MeshCount:
    """(n_c² + 4 n_c n_r) n_x hexahedra; nodes per section counted per block less the shared edges."""
    n_c, n_r, n_x = cylinder_divisions(spec.radius, spec.length, mesh.size)
    p = 2 if mesh.order == 2 else 1
    # the centre's (p n_c + 1)² nodes, each ring block's p n_r rows of p n_c + 1 less its radial
    # edge shared with the next block
    section_nodes = (p * n_c + 1) ** 2 + 4 * (p * n_c) * (p * n_r)
    elements = (n_c * n_c + 4 * n_c * n_r) * n_x * (6 if mesh.cell == "tet" else 1)  # P2 nodes = Q2 nodes
    return MeshCount(elements, section_nodes * (p * n_x + 1), 3, "cylinder O-grid divisions")


SHAPE = Shape(
    "cylinder", ("radius", "length"), parse_cylinder,
    lambda spec, mesh, gauge: cylinder_specimen(spec, mesh.size, mesh.cell, gauge),
    tests={"confined-compression": ("die",), "torsion": ("clamped",)},
    thickness=lambda spec: 2.0 * spec.radius, count=count_cylinder,
    doc="solid circular cylinder along x (O-grid of hexahedra, or each split into six tetrahedra): confined "
        "compression in a die, torsion")
