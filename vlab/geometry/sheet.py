"""Thin rectangular sheet in the x-y plane, tested in plane stress (or plane strain): a 2D mesh.

Length L along x (first loading axis), width W along y, thickness t through z, in mm. Structured
mesh of ceil(side / size) divisions per side: quadrilaterals, or each split into two triangles
(scikit-fem's tensor-product meshes). The grips are the four edges normal to x and y. The
extensometer marks lie on the centre lines, centred on the sheet (gauge length L/2 by default);
the transverse marks span the width at the centre; the thickness "marks" are the two faces
(z = 0 and z = t) over the centre, read through the out-of-plane stretch λ₃ of the plane law.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import skfem

from vlab import fields
from vlab.geometry.counts import div, lattice_count
from vlab.geometry.shape import Shape

from vlab.geometry.specimen import GaugeMarks, Grip, SizedSpec, Specimen


def sheet_mesh(size: tuple[float, float], element_size: float, cell: str) -> skfem.Mesh:
    axes = [np.linspace(0.0, side, max(1, math.ceil(side / element_size - 1e-9)) + 1) for side in size]
    mesh_type = skfem.MeshQuad if cell == "quad" else skfem.MeshTri
    return mesh_type.init_tensor(*axes)


def _edge(axis: int, value: float, tol: float):
    return lambda X: np.abs(X[:, axis] - value) <= tol


def sheet_specimen(size, thickness: float, element_size: float, cell: str,
                   gauge_length: float | None = None) -> Specimen:
    """A sheet with grips on its x and y edges and gauge marks of ``gauge_length`` (default L/2)."""
    L, W = (float(s) for s in size)
    t = float(thickness)
    tol = 1e-9 * max(L, W)
    grips = (
        Grip("x-", 0, -1, _edge(0, 0.0, tol)), Grip("x+", 0, +1, _edge(0, L, tol)),
        Grip("y-", 1, -1, _edge(1, 0.0, tol)), Grip("y+", 1, +1, _edge(1, W, tol)),
    )
    gx = gauge_length or L / 2
    gy = W / 2 if gauge_length is None else min(gauge_length, W)
    return Specimen(
        shape="sheet",
        mesh=sheet_mesh((L, W), element_size, cell),
        grips=grips,
        grip_separation={0: L, 1: W},
        extensometers={
            0: GaugeMarks((L / 2 - gx / 2, W / 2), (L / 2 + gx / 2, W / 2)),
            1: GaugeMarks((L / 2, W / 2 - gy / 2), (L / 2, W / 2 + gy / 2)),
        },
        transverse={
            0: GaugeMarks((L / 2, 0.0), (L / 2, W)),
            1: GaugeMarks((0.0, W / 2), (L, W / 2)),
        },
        thickness=GaugeMarks((L / 2, W / 2, 0.0), (L / 2, W / 2, t)),
        area0={0: W * t, 1: L * t},
        length_scale=float(np.linalg.norm([L, W, t])),
        sheet_thickness=t,
    )


@dataclass(frozen=True)
class SheetSpecimen(SizedSpec):
    """A thin sheet in the x-y plane, meshed in 2D (cells tri | quad) and solved in plane stress
    (P₃₃ = 0, the thickness follows the material) or plane strain (thickness held)."""

    shape: str
    size: tuple[float, float]  # mm: length (x, loading axis), width (y)
    thickness: float  # mm, through z
    plane: str = "stress"  # "stress" | "strain"
    cells = ("tri", "quad")  # 2D cells; the first is the default mesh.cell


def parse_sheet(t: fields.Table) -> SheetSpecimen:
    size = fields.vector(t.field("size"), t.get("size"), 2, "[length, width] in mm (a sheet is 2D; its "
                   "thickness is specimen.thickness)", gt=0)
    thickness = t.number("thickness", gt=0, note=" (mm)")
    return SheetSpecimen(shape="sheet", size=size, thickness=thickness,  # type: ignore[arg-type]
                         plane=t.choice("plane", ("stress", "strain"), default="stress"))


SHAPE = Shape(
    "sheet", ("size", "thickness", "plane"), parse_sheet,
    lambda spec, mesh, gauge: sheet_specimen(spec.size, spec.thickness, mesh.size, mesh.cell, gauge),
    tests={"uniaxial": ("roller", "clamped"), "biaxial": ("roller", "clamped"), "planar": ("roller",)},
    count=lambda spec, mesh: lattice_count((div(spec.size[0], mesh.size), div(spec.size[1], mesh.size)), mesh,
                                           "sheet divisions"),  # n_x n_y quadrilaterals (two triangles each)
    doc="thin sheet in plane stress or plane strain (2D)")
