"""Double-lap shear sandwich: two equal rubber layers bonded between three rigid plates.

Each layer is ``length`` L along x (the shear direction), ``gap`` H along y (its thickness) and
``depth`` D along z, in mm; the central plate (``plate_thickness`` p, not meshed: it is rigid)
separates them, layer A at 0 ≤ y ≤ H and layer B at H + p ≤ y ≤ 2H + p. The outer plates
(y = 0 and y = 2H + p) hold; the central plate (y = H and y = H + p) moves along x by γ H with
the gaps held (vlab.loading.shear_grips.plate_shear, the grips ``outer`` and ``centre``). The
load cell reads the central plate, the bonded area is both layers', A₀ = 2 L D, so the nominal
shear stress is F_s / (2 L D); the normal forces of the two layers cancel on the central plate
(what the double lap is built for: no net bending or peel load on the machine). By the mirror
symmetry about the central plate each layer deforms as a single-lap specimen (geometry/shear.py)
of the same size. Gauge marks across layer A on its free face z = D; the region "core"
(|x − L/2| ≤ L/4, |z − D/2| ≤ D/4, both layers) is where the centre stress is read (its σ_xy
average cancels between the layers, sheared in opposite senses; the normal stresses, even in γ,
and the field probe, which reads each element in its own sense, do not).

The renders show it face-on with its three plates (vlab.geometry.shear.face_on), the outer ones
drawn as thick as the central one.

Keys: ``length``, ``gap``, ``depth``, ``plate_thickness`` (mm, > 0), length ≥ 2 × gap.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab import fields
from vlab.geometry.block import block_mesh
from vlab.geometry.shape import Shape
from vlab.geometry.shear import count_layers, face_on, parse_shear
from vlab.geometry.specimen import GaugeMarks, Grip, Specimen


@dataclass(frozen=True)
class DoubleLapSpecimen:
    shape: str
    length: float  # mm, x: shear direction
    gap: float  # mm, y: each layer's thickness
    depth: float  # mm, z
    plate_thickness: float  # mm, the rigid central plate between the layers

    @property
    def max_dimension(self) -> float:
        return max(self.length, 2 * self.gap + self.plate_thickness, self.depth)


def parse_double_lap(t: fields.Table) -> DoubleLapSpecimen:
    layer = parse_shear(t)  # length, gap, depth and their checks, as for one layer
    return DoubleLapSpecimen(shape="double-lap", length=layer.length, gap=layer.gap, depth=layer.depth,
                             plate_thickness=t.number("plate_thickness", gt=0, note=" (mm, the central plate)"))


def double_lap_specimen(spec: DoubleLapSpecimen, element_size: float, cell: str) -> Specimen:
    L, H, D, p = spec.length, spec.gap, spec.depth, spec.plate_thickness
    tol = 1e-9 * spec.max_dimension
    layer = block_mesh((L, H, D), element_size, cell)
    top = 2 * H + p

    def at(*values):
        return lambda X: np.any([np.abs(X[:, 1] - v) <= tol for v in values], axis=0)

    return Specimen(
        shape="double-lap",
        mesh=layer + layer.translated((0.0, H + p, 0.0)),
        grips=(Grip("outer", 1, -1, at(0.0, top)), Grip("centre", 1, +1, at(H, H + p))),
        grip_separation={0: L, 1: H},
        extensometers={0: GaugeMarks((L / 4, H / 2, D), (3 * L / 4, H / 2, D)),
                       1: GaugeMarks((L / 2, H / 4, D), (L / 2, 3 * H / 4, D))},
        transverse={0: GaugeMarks((L / 2, 0.0, D / 2), (L / 2, H, D / 2))},
        thickness=GaugeMarks((L / 2, H / 2, 0.0), (L / 2, H / 2, D)),
        area0={0: 2 * H * D, 1: 2 * L * D},
        length_scale=float(np.linalg.norm([L, top, D])),
        regions={"core": lambda c: (np.abs(c[:, 0] - L / 2) <= L / 4) & (np.abs(c[:, 2] - D / 2) <= D / 4)},
        view=face_on(spec, [(-p, 0.0, "held"), (H, H + p, "moved"), (top, top + p, "held")]),
    )


SHAPE = Shape(
    "double-lap", ("length", "gap", "depth", "plate_thickness"), parse_double_lap,
    lambda spec, mesh, gauge: double_lap_specimen(spec, mesh.size, mesh.cell),
    tests={"simple-shear": ("plates",)},
    count=lambda spec, mesh: count_layers(spec, mesh, layers=2),  # two layers, as one of twice the gap
    doc="double-lap shear sandwich: two layers, outer plates held, the central plate moved",
    gauge_from="the layer's shear (its marks span the middle half of the layer)")
