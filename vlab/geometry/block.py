"""Rectangular block specimen: length x (first loading axis), width y, thickness z, in mm.

Structured mesh of ceil(side / size) divisions per side: hexahedra, or each hexahedron split into
tetrahedra (scikit-fem's tensor-product tet mesh). A symmetry-reduced block ([mesh] symmetry) is
the part x ≥ L/2 (, y ≥ W/2, z ≥ H/2) of the mirror-built mesh (geometry/lattice.py): one octant
of ceil(side / (2 size)) divisions per half side, mirrored across the planes not cut. With an even
number of divisions per side its hexahedra are exactly those of the full mesh; its tetrahedra are
the octant's Kuhn split, not scikit-fem's (the same only up to discretisation error on a
non-uniform field, e.g. with clamped grips). The grips are the four side faces normal to x and y;
the extensometer marks sit on the top face (z = thickness) centred on the block.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import skfem

from vlab import fields
from vlab.geometry.lattice import Lattice, divisions, swept_mesh, symmetric_mesh
from vlab.geometry.counts import CUT, MeshCount, div, lattice_count
from vlab.geometry.shape import Shape
from vlab.geometry.specimen import GaugeMarks, Grip, SizedSpec, Specimen
from vlab.geometry.symmetry import cut_axes, mirrored_planes


def block_mesh(size: tuple[float, float, float], element_size: float, cell: str,
               symmetry: str = "none") -> skfem.Mesh:
    if symmetry == "none":
        axes = [np.linspace(0.0, side, divisions(side, element_size) + 1) for side in size]
        return swept_mesh((skfem.MeshHex if cell == "hex" else skfem.MeshTet).init_tensor(*axes))
    axes = [np.linspace(side / 2, side, divisions(side / 2, element_size) + 1) for side in size]
    X = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)
    planes = [(a, size[a] / 2) for a in mirrored_planes(symmetry)]
    return symmetric_mesh(Lattice.block(X), planes, cell, max(size))


def _face(axis: int, value: float, tol: float):
    return lambda X: np.abs(X[:, axis] - value) <= tol


def block_specimen(size, element_size: float, cell: str, gauge_length: float | None = None,
                   symmetry: str = "none") -> Specimen:
    """A block with grips on its x and y faces and gauge marks of ``gauge_length`` (default L/2)."""
    L, W, H = (float(s) for s in size)
    tol = 1e-9 * max(L, W, H)
    cut = cut_axes(symmetry)
    grips = tuple(g for g in (
        Grip("x-", 0, -1, _face(0, 0.0, tol)), Grip("x+", 0, +1, _face(0, L, tol)),
        Grip("y-", 1, -1, _face(1, 0.0, tol)), Grip("y+", 1, +1, _face(1, W, tol)),
    ) if not (g.side < 0 and g.axis in cut))
    gx = gauge_length or L / 2
    gy = W / 2 if gauge_length is None else min(gauge_length, W)
    return Specimen(
        shape="block",
        mesh=block_mesh((L, W, H), element_size, cell, symmetry),
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
        symmetry=tuple((a, (L, W, H)[a] / 2) for a in cut),
    )


@dataclass(frozen=True)
class BlockSpecimen(SizedSpec):
    shape: str
    size: tuple[float, float, float]  # mm: length (x, loading axis), width (y), thickness (z)


def parse_block(t: fields.Table) -> BlockSpecimen:
    size = fields.vector(t.field("size"), t.get("size"), 3, "[length, width, thickness] in mm", gt=0)
    return BlockSpecimen(shape="block", size=size)  # type: ignore[arg-type]


def count_block(spec, mesh) -> MeshCount:
    """n_i = ceil(side_i / h) divisions per side (vlab.geometry.lattice.divisions), per half side and
    mirrored for a symmetry-reduced block, which meshes 1/2, 1/4, 1/8 of it."""
    cut = CUT.get(mesh.symmetry, 0)
    n = tuple(div(s / 2, mesh.size) * (1 if a < cut else 2) if cut else div(s, mesh.size)
              for a, s in enumerate(spec.size))
    return lattice_count(n, mesh, "block divisions")


SHAPE = Shape(
    "block", ("size",), parse_block,
    lambda spec, mesh, gauge: block_specimen(spec.size, mesh.size, mesh.cell, gauge, mesh.symmetry),
    tests={"uniaxial": ("roller", "clamped"), "biaxial": ("roller", "clamped"), "planar": ("roller",),
           "simple-shear": ("kinematic",), "confined-compression": ("die",)},
    symmetric=True, thickness=lambda spec: float(min(spec.size[1], spec.size[2])), count=count_block,
    doc="rectangular block; the roller block is every stretch kind's oracle, the kinematic block simple shear's")
