"""Rectangular block specimen: length x (first loading axis), width y, thickness z, in mm.

Structured mesh of ceil(side / size) divisions per side: hexahedra, or each hexahedron split into
tetrahedra (scikit-fem's tensor-product tet mesh). The grips are the four side faces normal to x
and y; the extensometer marks sit on the top face (z = thickness) centred on the block.
"""

from __future__ import annotations

import math

import numpy as np
import skfem

from vlab.geometry.specimen import GaugeMarks, Grip, Specimen


def block_mesh(size: tuple[float, float, float], element_size: float, cell: str) -> skfem.Mesh:
    axes = [np.linspace(0.0, side, max(1, math.ceil(side / element_size - 1e-9)) + 1) for side in size]
    mesh_type = skfem.MeshHex if cell == "hex" else skfem.MeshTet
    return mesh_type.init_tensor(*axes)


def _face(axis: int, value: float, tol: float):
    return lambda X: np.abs(X[:, axis] - value) <= tol


def block_specimen(size, element_size: float, cell: str, gauge_length: float | None = None) -> Specimen:
    """A block with grips on its x and y faces and gauge marks of ``gauge_length`` (default L/2)."""
    L, W, H = (float(s) for s in size)
    tol = 1e-9 * max(L, W, H)
    grips = (
        Grip("x-", 0, -1, _face(0, 0.0, tol)), Grip("x+", 0, +1, _face(0, L, tol)),
        Grip("y-", 1, -1, _face(1, 0.0, tol)), Grip("y+", 1, +1, _face(1, W, tol)),
    )
    gx = gauge_length or L / 2
    gy = W / 2 if gauge_length is None else min(gauge_length, W)
    return Specimen(
        shape="block",
        mesh=block_mesh((L, W, H), element_size, cell),
        grips=grips,
        grip_separation={0: L, 1: W},
        extensometers={
            0: GaugeMarks((L / 2 - gx / 2, W / 2, H), (L / 2 + gx / 2, W / 2, H)),
            1: GaugeMarks((L / 2, W / 2 - gy / 2, H), (L / 2, W / 2 + gy / 2, H)),
        },
        transverse={
            0: GaugeMarks((L / 2, 0.0, H / 2), (L / 2, W, H / 2)),
            1: GaugeMarks((0.0, W / 2, H / 2), (L, W / 2, H / 2)),
        },
        thickness=GaugeMarks((L / 2, W / 2, 0.0), (L / 2, W / 2, H)),
        area0={0: W * H, 1: L * H},
        length_scale=float(np.linalg.norm([L, W, H])),
    )
