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

import numpy as np
import skfem

from vlab.geometry.specimen import GaugeMarks, Grip, Specimen


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
