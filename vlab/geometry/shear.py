"""Shear specimen: a rubber block bonded between two rigid plates (a single-lap shear test).

Length L along x (the shear direction), gap H along y (the block's thickness between the plates),
depth D along z, in mm. The plate y = 0 holds; the plate y = H moves along x with the normal gap
held (vlab.loading.shear_grips.plate_shear). The faces x = 0, L and z = 0, D are free, so the
stress is not the homogeneous simple shear near them (the edge effects a lab sees: the free ends
carry no shear traction, the plates' normal force concentrates at the corners). Gauge marks on the
free face z = D at x = L/2 over the middle half of the gap read the local shear (ShearGauge); the
region "core" (|x − L/2| ≤ L/4, |z − D/2| ≤ D/4) is where the centre stress and the distance from
simple shear are read (measure/shear.py).

The renders look at the face z = D face-on (the view direction is the normal of the shear plane
x–y, so the layer's parallelogram shows undistorted) and draw the rigid plates, ``gap``/2 thick
(the plates' thickness is not modelled: they are rigid), each reaching a quarter of the length
beyond the layer on the side where its machine grip holds it (the held plate to the left, the moved
one to the right).

Keys: ``length``, ``gap``, ``depth`` (mm, > 0), length ≥ 2 × gap (a thin layer: a taller block
bends more than it shears), else a SceneError naming the key and its range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.block import block_mesh
from vlab.geometry.counts import MeshCount, div, lattice_count
from vlab.geometry.shape import Shape
from vlab.geometry.specimen import GaugeMarks, Grip, Plate, Specimen, View

LENGTH_OVER_GAP_MIN = 2.0


@dataclass(frozen=True)
class ShearSpecimen:
    shape: str
    length: float  # mm, x: shear direction
    gap: float  # mm, y: between the plates
    depth: float  # mm, z

    @property
    def max_dimension(self) -> float:
        return max(self.length, self.gap, self.depth)


def parse_shear(t: fields.Table) -> ShearSpecimen:
    length = t.number("length", gt=0, note=" (mm, along the shear)")
    gap = t.number("gap", gt=0, note=" (mm, between the plates)")
    depth = t.number("depth", gt=0, note=" (mm)")
    if length < LENGTH_OVER_GAP_MIN * gap:
        raise SceneError(f"{t.field('length')} must be >= {LENGTH_OVER_GAP_MIN:g} x specimen.gap = "
                         f"{LENGTH_OVER_GAP_MIN * gap:g} mm (a shear layer is thin: length/gap >= "
                         f"{LENGTH_OVER_GAP_MIN:g}), got {length:g}")
    return ShearSpecimen(shape="shear", length=length, gap=gap, depth=depth)


def face_on(spec, layers: list[tuple[float, float, str]]) -> View:
    """The view of a shear specimen from +z (screen up +y), with plates: ``layers`` lists each plate as
    (y0, y1, side), side "held" (reaching L/4 beyond x = 0, where its grip holds it) or "moved"
    (beyond x = L)."""
    L, D = spec.length, spec.depth
    reach = {"held": (-L / 4, L), "moved": (0.0, 1.25 * L)}
    plates = tuple(Plate((reach[side][0], y0, 0.0), (reach[side][1], y1, D)) for y0, y1, side in layers)
    return View(direction=(0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0), plates=plates)


def shear_specimen(spec: ShearSpecimen, element_size: float, cell: str) -> Specimen:
    L, H, D = spec.length, spec.gap, spec.depth
    tol = 1e-9 * max(L, H, D)
    return Specimen(
        shape="shear",
        mesh=block_mesh((L, H, D), element_size, cell),
        grips=(Grip("y-", 1, -1, lambda X: np.abs(X[:, 1]) <= tol),
               Grip("y+", 1, +1, lambda X: np.abs(X[:, 1] - H) <= tol)),
        grip_separation={0: L, 1: H},
        extensometers={0: GaugeMarks((L / 4, H / 2, D), (3 * L / 4, H / 2, D)),
                       1: GaugeMarks((L / 2, H / 4, D), (L / 2, 3 * H / 4, D))},
        transverse={0: GaugeMarks((L / 2, 0.0, D / 2), (L / 2, H, D / 2))},  # the gap at the centre
        thickness=GaugeMarks((L / 2, H / 2, 0.0), (L / 2, H / 2, D)),
        area0={0: H * D, 1: L * D},
        length_scale=float(np.linalg.norm([L, H, D])),
        regions={"core": lambda c: (np.abs(c[:, 0] - L / 2) <= L / 4) & (np.abs(c[:, 2] - D / 2) <= D / 4)},
        view=face_on(spec, [(-H / 2, 0.0, "held"), (H, 1.5 * H, "moved")]),
    )


def count_layers(spec, mesh, layers: int = 1) -> MeshCount:
    """As a block of the layer's dimensions; ``layers`` layers counted as one of that many gaps."""
    n = (div(spec.length, mesh.size), layers * div(spec.gap, mesh.size), div(spec.depth, mesh.size))
    return lattice_count(n, mesh, "layer divisions")


SHAPE = Shape(
    "shear", ("length", "gap", "depth"), parse_shear,
    lambda spec, mesh, gauge: shear_specimen(spec, mesh.size, mesh.cell),
    tests={"simple-shear": ("plates",)}, count=count_layers,
    doc="rubber layer bonded between rigid shear plates, one held, one moved tangentially",
    gauge_from="the layer's shear (its marks span the middle half of the layer)")
