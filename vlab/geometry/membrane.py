"""Circular membrane (the bulge-test sheet): ``radius`` a (the clamped rim) and ``thickness`` t (mm),
in the x–y plane from z = 0 (the face the liquid presses) to z = t, centred on the z axis; meshed as
its quarter x, y ≥ 0 (the symmetry-reduced model of an axisymmetric test: the bulge,
vlab.loading.bulge).

Hexahedra by a quarter O-grid of the disc (the cylinder's section, vlab.geometry.cylinder, cut to
one quadrant): a central square [0, a/2]² and two ring blocks between its outer edges and the
arcs θ ∈ [0, π/4] and [π/4, π/2], swept through the thickness:

    m = ⌈π a / (4 h)⌉ divisions per ring block's arc,  n_r = ⌈a / (2 h)⌉ radially,
    n_z = ⌈t / h⌉ layers   (h = mesh.size),   elements (m² + 2 m n_r) n_z.

Every rim node lies on r = a, so the facetted disc is inscribed. A thin sheet (t ≪ h) has one
layer: its elements are flat (aspect ratio h / t), which membrane action does not mind; bending
near the rim, which it does mind, is a boundary layer of width ~t that a membrane test ignores.

Named places: the region "rim" selects the nodes on r = a (clamped), "bottom" the face z = 0 (the
liquid's), the planes x = 0 and y = 0 are the symmetry planes (the readings scale by 4 where they
are whole-specimen quantities); the gauge marks are the pole's top node (0, 0, t) with
(a/2, 0, t) along the meridian, (0, a/2, t) across it, and the pole's thickness (0, 0, 0)–(0, 0, t).
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
from vlab.geometry.specimen import GaugeMarks, Specimen, View

__all__ = ["MembraneSpecimen", "membrane_divisions", "membrane_mesh", "membrane_specimen", "chamber_volume",
           "SHAPE"]

INNER = 0.5  # half-side of the O-grid's central square / radius (as the cylinder's)


@dataclass(frozen=True)
class MembraneSpecimen:
    shape: str
    radius: float  # mm, the clamped rim
    thickness: float  # mm

    @property
    def length(self) -> float:
        return self.radius

    @property
    def max_dimension(self) -> float:
        return 2.0 * self.radius


def parse_membrane(t: fields.Table) -> MembraneSpecimen:
    radius = t.number("radius", gt=0, note=" (mm, the clamped rim)")
    thickness = t.number("thickness", gt=0, note=" (mm)")
    if thickness > radius / 5.0:
        raise SceneError(f"specimen.thickness must be <= specimen.radius / 5 = {radius / 5.0:g} mm for "
                         f"shape = 'membrane' (a sheet; a thicker disc is a plate), got {thickness:g}")
    return MembraneSpecimen(shape="membrane", radius=radius, thickness=thickness)


def membrane_divisions(radius: float, thickness: float, size: float) -> tuple[int, int, int]:
    """(m, n_r, n_z) of the module docstring."""
    return div(math.pi * radius / 4.0, size), div(radius / 2.0, size), div(thickness, size)


def _quarter_blocks(a: float, m: int, n_r: int) -> list[np.ndarray]:
    """The quarter O-grid's three blocks as node grids (nj, nk, 2) in the x–y plane."""
    c = INNER * a
    s = np.linspace(0.0, c, m + 1)
    blocks = [np.stack(np.meshgrid(s, s, indexing="ij"), axis=-1)]
    w = np.linspace(0.0, 1.0, n_r + 1)
    theta = np.linspace(0.0, math.pi / 4, m + 1)
    edges = [(np.stack([np.full(m + 1, c), s], -1), theta),  # x = c, facing θ ∈ [0, π/4]
             (np.stack([c - s, np.full(m + 1, c)], -1), math.pi / 4 + theta)]  # y = c, θ ∈ [π/4, π/2]
    for inner, angles in edges:
        outer = a * np.stack([np.cos(angles), np.sin(angles)], -1)
        blocks.append(inner[:, None, :] + w[None, :, None] * (outer - inner)[:, None, :])
    return blocks


def membrane_mesh(radius: float, thickness: float, size: float):
    """The quarter disc's hexahedral MeshHex (module docstring)."""
    m, n_r, n_z = membrane_divisions(radius, thickness, size)
    z = np.linspace(0.0, thickness, n_z + 1)
    lattice = None
    for block in _quarter_blocks(radius, m, n_r):
        X = np.empty((*block.shape[:2], n_z + 1, 3))
        X[..., :2] = block[:, :, None, :]
        X[..., 2] = z[None, None, :]
        d1, d2 = block[1, 0] - block[0, 0], block[0, 1] - block[0, 0]
        if d1[0] * d2[1] - d1[1] * d2[0] < 0:  # lattice order must be right-handed (J > 0)
            X = X[::-1]
        part = Lattice.block(np.ascontiguousarray(X))
        lattice = part if lattice is None else lattice.join(part, 1e-9 * radius)
    return lattice.to_mesh("hex")


def chamber_volume(radius: float) -> float:
    """V₀ = π a³ / 4 (mm³): the quarter of the liquid chamber under the sheet, a cylinder of the
    sheet's radius and depth a; the bulge test's volume ratio is (V₀ + V_bulge) / V₀."""
    return math.pi * radius**3 / 4.0


def membrane_specimen(spec: MembraneSpecimen, element_size: float, cell: str) -> Specimen:
    a, t = spec.radius, spec.thickness
    if cell != "hex":
        raise SceneError(f"mesh.cell must be 'hex' for specimen.shape = 'membrane' (a quarter O-grid of "
                         f"hexahedra), got {cell!r}")
    c = INNER * a
    tol = 1e-9 * a
    return Specimen(
        shape="membrane",
        mesh=membrane_mesh(a, t, element_size),
        grips=(),
        grip_separation={0: a},
        extensometers={0: GaugeMarks((0.0, 0.0, t), (c, 0.0, t))},
        transverse={0: GaugeMarks((0.0, 0.0, t), (0.0, c, t))},
        thickness=GaugeMarks((0.0, 0.0, 0.0), (0.0, 0.0, t)),
        area0={0: chamber_volume(a)},  # the quarter chamber's liquid volume V₀, mm³
        length_scale=a,
        regions={"rim": lambda X: np.hypot(X[:, 0], X[:, 1]) >= a - 1e-9 * a,
                 "bottom": lambda X: np.abs(X[:, 2]) <= tol,
                 "pole": lambda X: np.hypot(X[:, 0], X[:, 1]) <= tol},
        # from the side, a little above the sheet: the dome's profile on the cut plane y = 0, as a
        # bulge tester's side camera sees the pole height
        view=View(direction=(0.3, -1.0, 0.45), up=(0.0, 0.0, 1.0)),
    )


def count_membrane(spec, mesh) -> MeshCount:
    """(m² + 2 m n_r) n_z hexahedra; nodes per layer (p m + 1)² + 2 (p m + 1)(p n_r) − p n_r (the two
    ring blocks share their radial edge on θ = π/4), (p n_z + 1) layers for order p."""
    m, n_r, n_z = membrane_divisions(spec.radius, spec.thickness, mesh.size)
    p = 2 if mesh.order == 2 else 1
    layer = (p * m + 1) ** 2 + 2 * (p * m + 1) * (p * n_r) - p * n_r
    return MeshCount((m * m + 2 * m * n_r) * n_z, layer * (p * n_z + 1), 3, "membrane quarter O-grid")


SHAPE = Shape(
    "membrane", ("radius", "thickness"), parse_membrane,
    lambda spec, mesh, gauge: membrane_specimen(spec, mesh.size, mesh.cell),
    tests={"inflation": ("clamped",)}, thickness=lambda spec: spec.thickness, count=count_membrane,
    doc="circular sheet clamped at its rim, meshed as its quarter: the bulge test (inflation under volume control)",
    gauge_from="the pole (the bulge test reads the pole stretch and height)")
