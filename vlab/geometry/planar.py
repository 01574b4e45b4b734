"""Planar-tension (pure-shear) specimen: a wide, short strip clamped along its two long edges.

Height H along x (the loading axis: the free distance between the clamps), width W along y (the
long edges, W/H ≥ 10), thickness T along z, in mm. The clamps hold every component on the faces
x = 0 (fixed) and x = H (moved along x): the lateral stretch is held at 1 there, and far from the
free ends y = 0, W it stays 1 through the height, so the centre of the strip is close to pure
shear F = diag(λ, 1, t) (vlab.loading.kinds.planar); near the free ends the strip contracts
sideways as in a uniaxial test. Structured mesh as for the block (hexahedra, or tetrahedra split
from them). Gauge marks along x over the middle half of the height at the centre of the top face,
transverse marks across the middle half of the width, thickness marks through the centre; the
region "gauge" (|x − H/2| ≤ H/4, |y − W/2| ≤ W/4) is where the distance from pure shear is read
(measure/planar.py).

Keys: ``height``, ``width``, ``thickness`` (mm, > 0); width/height ≥ 10 and thickness ≤ height
(a thin strip), else a SceneError naming the key and its range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.block import block_mesh
from vlab.geometry.counts import div, lattice_count
from vlab.geometry.shape import Shape
from vlab.geometry.specimen import GaugeMarks, Grip, Specimen

ASPECT_MIN = 10.0  # width / height of a planar-tension strip


@dataclass(frozen=True)
class PlanarSpecimen:
    shape: str
    height: float  # mm, x: between the clamps (loading axis)
    width: float  # mm, y: along the clamped edges
    thickness: float  # mm, z

    @property
    def length(self) -> float:
        return self.height

    @property
    def max_dimension(self) -> float:
        return self.width


def parse_planar(t: fields.Table) -> PlanarSpecimen:
    height = t.number("height", gt=0, note=" (mm, between the clamps)")
    width = t.number("width", gt=0, note=" (mm, along the clamps)")
    thickness = t.number("thickness", gt=0, note=" (mm)")
    if width < ASPECT_MIN * height:
        raise SceneError(f"{t.field('width')} must be >= {ASPECT_MIN:g} x specimen.height = "
                         f"{ASPECT_MIN * height:g} mm (a planar-tension strip is wide and short, width/height >= "
                         f"{ASPECT_MIN:g}), got {width:g}")
    if thickness > height:
        raise SceneError(f"{t.field('thickness')} must be <= specimen.height = {height:g} mm (a thin strip), "
                         f"got {thickness:g}")
    return PlanarSpecimen(shape="planar-tension", height=height, width=width, thickness=thickness)


def planar_specimen(spec: PlanarSpecimen, element_size: float, cell: str,
                    gauge_length: float | None = None) -> Specimen:
    """The strip with clamps on x = 0 and x = H and marks of ``gauge_length`` (default H/2)."""
    H, W, T = spec.height, spec.width, spec.thickness
    tol = 1e-9 * W
    g = gauge_length or H / 2
    return Specimen(
        shape="planar-tension",
        mesh=block_mesh((H, W, T), element_size, cell),
        grips=(Grip("x-", 0, -1, lambda X: np.abs(X[:, 0]) <= tol),
               Grip("x+", 0, +1, lambda X: np.abs(X[:, 0] - H) <= tol)),
        grip_separation={0: H},
        extensometers={0: GaugeMarks((H / 2 - g / 2, W / 2, T), (H / 2 + g / 2, W / 2, T))},
        transverse={0: GaugeMarks((H / 2, W / 4, T / 2), (H / 2, 3 * W / 4, T / 2))},
        thickness=GaugeMarks((H / 2, W / 2, 0.0), (H / 2, W / 2, T)),
        area0={0: W * T},
        length_scale=float(np.linalg.norm([H, W, T])),
        regions={"gauge": lambda c: (np.abs(c[:, 0] - H / 2) <= H / 4) & (np.abs(c[:, 1] - W / 2) <= W / 4)},
    )


SHAPE = Shape(
    "planar-tension", ("height", "width", "thickness"), parse_planar,
    lambda spec, mesh, gauge: planar_specimen(spec, mesh.size, mesh.cell, gauge),
    tests={"planar": ("clamped",)},
    count=lambda spec, mesh: lattice_count(  # as a block of its dimensions
        (div(spec.height, mesh.size), div(spec.width, mesh.size), div(spec.thickness, mesh.size)), mesh,
        "strip divisions"),
    doc="planar-tension strip, width/height >= 10, clamped along its long edges")
