"""``[mesh]``: element size, order, cell, gauge refinement, quality floor, formulation, symmetry.

Defaults: order = 1, cell = the specimen's first (tet; tri for a sheet), min_quality = 0.15,
formulation = "displacement", symmetry = "none", max_dofs = none (the size budget's default,
vlab/geometry/budget.py, checked before meshing). ``formulation = "mixed"`` (locking-free for
ν → ½) needs a model with a volumetric–isochoric split (``split`` in vlab.materials.registry) and hexes or order-2 tets.
An imported mesh is meshed already: its size is the mean edge length of its cells.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.symmetry import SYMMETRY_LEVELS
from vlab.materials.registry import MODELS as REGISTRY
from vlab.geometry.shapes import SHAPES
from vlab.scene.specimen import MeshFileSpecimen, Specimen

if TYPE_CHECKING:
    from vlab.scene.test import TestSpec

__all__ = ["MeshSpec", "FORMULATIONS", "parse_mesh", "check_formulation", "check_symmetry"]


FORMULATIONS = ("displacement", "mixed")  # mesh.formulation


@dataclass(frozen=True)
class MeshSpec:
    size: float  # target element edge, mm
    order: int  # 1 or 2
    cell: str  # "tet" or "hex"; "tri" or "quad" for a sheet
    gauge_size: float | None = None  # element edge over a dogbone's parallel section and fillets
    min_quality: float = 0.15  # smallest acceptable element quality (geometry/quality.py)
    formulation: str = "displacement"  # or "mixed": condensed θ/p per element (vlab/fe/mixed.py)
    symmetry: str = "none"  # none | half | quarter | eighth (geometry/symmetry.py)
    max_dofs: int | None = None  # size budget (vlab/geometry/budget.py); None = its default
    mesher: str = "vlab"  # dogbone tetrahedra: "vlab" (hexahedra split) | "gmsh" (Delaunay; the cad extra)


def parse_mesh(raw: Any, specimen: Specimen) -> MeshSpec:
    t = fields.Table("mesh", raw, ("size", "order", "cell", "gauge_size", "min_quality", "symmetry", "formulation",
                                   "max_dofs", "mesher"))
    max_dofs = t.get("max_dofs", None)
    max_dofs = None if max_dofs is None else fields.integer(t.field("max_dofs"), max_dofs, 1, 10**12)
    if specimen.shape == "cad" and t.get("cell", "tet") != "tet":
        raise SceneError(f"{t.field('cell')} must be 'tet' for specimen.shape = 'cad' (Gmsh meshes it in "
                         f"tetrahedra), got {fields.show(t.raw['cell'])}")
    if specimen.shape == "mesh":
        return dataclasses.replace(_parse_mesh_of_file(t, specimen), max_dofs=max_dofs)
    size = t.number("size", gt=0, le=specimen.max_dimension, note=" (the largest specimen dimension)")
    gauge_size = t.number("gauge_size", default=None, gt=0, le=size, note=" (mesh.size)")
    if gauge_size is not None and not SHAPES[specimen.shape].gauge_size:
        fine = [name for name, s in SHAPES.items() if s.gauge_size]
        raise SceneError(f"{t.field('gauge_size')} applies to specimen.shape = "
                         f"{' or '.join(map(repr, fine))} only, not {specimen.shape!r}")
    symmetry = t.choice("symmetry", SYMMETRY_LEVELS, default="none")
    if symmetry != "none" and not SHAPES[specimen.shape].symmetric:
        mirrored = [name for name, s in SHAPES.items() if s.symmetric]
        raise SceneError(f"{t.field('symmetry')} must be 'none' for specimen.shape = {specimen.shape!r} "
                         f"(symmetry reduction is for {', '.join(mirrored)}), got {symmetry!r}")
    cells = getattr(specimen, "cells", ("tet", "hex"))  # a specimen's own cells (2D: tri, quad)
    cell = t.choice("cell", cells, default=cells[0])
    return MeshSpec(size=size, order=t.integer("order", 1, 2, default=1), mesher=_mesher(t, specimen, cell, symmetry),
                    cell=cell, gauge_size=gauge_size,
                    min_quality=t.number("min_quality", default=0.15, gt=0, lt=1), symmetry=symmetry,
                    formulation=t.choice("formulation", FORMULATIONS, default="displacement"), max_dofs=max_dofs)


def _mesher(t: fields.Table, specimen: Specimen, cell: str, symmetry: str) -> str:
    """``mesher = "gmsh"``: a dogbone's tetrahedra from Gmsh (whole specimen, tet cells, Gmsh installed)."""
    mesher = t.choice("mesher", ("vlab", "gmsh"), default="vlab")
    if mesher == "gmsh":
        from vlab.geometry.cad import gmsh_version

        if specimen.shape != "dogbone" or cell != "tet" or symmetry != "none":
            raise SceneError(f"{t.field('mesher')} = 'gmsh' meshes a dogbone in tetrahedra: needs specimen.shape "
                             f"= 'dogbone', mesh.cell = 'tet', mesh.symmetry = 'none' (got {specimen.shape!r}, "
                             f"{cell!r}, {symmetry!r})")
        if gmsh_version() is None:
            raise SceneError(f"{t.field('mesher')} = 'gmsh' needs Gmsh: pip install \"vlab[cad]\"")
    return mesher


def _parse_mesh_of_file(t: fields.Table, specimen: MeshFileSpecimen) -> MeshSpec:
    """An imported mesh is meshed already: size and gauge_size do not apply, the cell kind is the
    file's; order (2 adds mid-edge nodes to tetrahedra) and min_quality do."""
    for key in ("size", "gauge_size"):
        if key in t.raw:
            raise SceneError(f"{t.field(key)} does not apply to specimen.shape = 'mesh' (the file is meshed "
                             f"already); remove it")
    cell = specimen.data.cell
    if t.get("cell", cell) != cell:
        raise SceneError(f"{t.field('cell')} must be {cell!r} (the cells of {specimen.spec.file.name}), "
                         f"got {fields.show(t.raw['cell'])}")
    symmetry = t.choice("symmetry", SYMMETRY_LEVELS, default="none")
    if symmetry != "none":
        raise SceneError(f"{t.field('symmetry')} must be 'none' for specimen.shape = 'mesh' (vlab cannot know "
                         f"that a user's mesh is symmetric), got {symmetry!r}")
    edges = specimen.data.points[specimen.data.cells[:, :2]]
    size = float(np.mean(np.linalg.norm(edges[:, 1] - edges[:, 0], axis=1)))
    return MeshSpec(size=size, order=t.integer("order", 1, 2, default=1), cell=cell,
                    min_quality=t.number("min_quality", default=0.15, gt=0, lt=1),
                    formulation=t.choice("formulation", FORMULATIONS, default="displacement"))


def check_formulation(mesh: MeshSpec, model: str) -> None:
    """The mixed formulation needs a split law and an element pair that does not lock."""
    if mesh.formulation != "mixed":
        return
    if REGISTRY[model].split is None:
        split = ", ".join(n for n, m in REGISTRY.items() if m.split is not None)
        raise SceneError(f"mesh.formulation = 'mixed' needs a material with a volumetric–isochoric "
                         f"split; material.model {model!r} has none (allowed with 'mixed': "
                         f"{split}; or use mesh.formulation = 'displacement')")
    if mesh.cell in ("tri", "quad"):
        raise SceneError("mesh.formulation = 'mixed' is for 3D solids (hex, or order-2 tet); a sheet "
                         "in plane stress has no volumetric locking (the thickness is free), so use "
                         "mesh.formulation = 'displacement'")
    if mesh.cell == "tet" and mesh.order == 1:
        raise SceneError("mesh.formulation = 'mixed' needs mesh.order = 2 with mesh.cell = 'tet' (or "
                         "mesh.cell = 'hex'): a linear tetrahedron has one constant J, so one pressure "
                         "per element constrains as much as the displacement model and still locks")


def check_symmetry(mesh: MeshSpec, test: TestSpec, specimen: Specimen) -> None:
    """Refuse a symmetry reduction of a set-up that is not symmetric: a block pulled biaxially
    between clamped grips, one of each pair fixed, shifts the y grips against the x clamps (which
    hold u_y = 0), so its solution is not mirror-symmetric. (Roller grips are: their 3-2-1
    supports pin rigid motions only and give way to the symmetry planes; dogbones and centred
    cruciforms are.)"""
    from vlab.loading.kinds import kind_of

    if mesh.symmetry != "none" and test.misalignment is not None:
        raise SceneError(f"mesh.symmetry must be 'none' with test.misalignment (a misaligned grip bends the "
                         f"specimen: the field is not mirror-symmetric), got {mesh.symmetry!r}")
    if mesh.symmetry != "none" and not kind_of(test).symmetric:
        raise SceneError(f"mesh.symmetry must be 'none' for test.kind = {test.kind!r} (its loading is not "
                         f"mirror-symmetric), got {mesh.symmetry!r}")
    if (mesh.symmetry != "none" and specimen.shape == "block" and test.kind == "biaxial"
            and test.grips == "clamped"):
        raise SceneError(f"mesh.symmetry must be 'none' for a biaxial block between clamped grips (one "
                         f"grip per axis holds, so the set-up is not mirror-symmetric), got {mesh.symmetry!r}; "
                         f"use test.grips = 'roller' or a cruciform")
