"""``[specimen]``: the shapes a scene may describe, each a frozen spec with ``length`` and
``max_dimension`` (mm) and a parser ``(fields.Table) -> spec``.

Dogbones: ``shape = "dogbone"`` with ``standard = "<name>"`` (dimensions shipped in
vlab/data/standards/) and/or the explicit keys of ``DIMENSION_KEYS`` (explicit keys win); tested
uniaxially between clamped grips. Sheets: ``shape = "sheet"`` with ``size = [length, width]``,
``thickness`` (mm) and ``plane = "stress"`` (default) or ``"strain"``; meshed in 2D. Cruciforms:
arm_width, arm_length, gauge_region, fillet_radius, thickness, grip_length and optional
slit_count, slit_width, slit_length; tested biaxially between four clamped grips. Imported meshes:
``shape = "mesh"`` with a file, grip region names, axis and marks.

New specimen shapes: a frozen dataclass and a parser here, registered in ``SPECIMEN_SHAPES`` (and
the test kinds and grips it allows in ``SPECIMEN_TESTS``). The shape registry of vlab.geometry
replaces these tables by delegation (issue 17).
"""

from __future__ import annotations

from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.cruciform import CRUCIFORM_KEYS, CruciformDimensions
from vlab.geometry.dogbone import DIMENSION_KEYS, DogboneDimensions, GeometryError
from vlab.geometry.imported import ImportedMesh, MeshImport, MeshImportError, read_mesh
from vlab.geometry.standards import standard_dimensions, standard_names

__all__ = ["BlockSpecimen", "DogboneSpecimen", "SheetSpecimen", "CruciformSpecimen", "MeshFileSpecimen",
           "Specimen", "SPECIMEN_SHAPES", "SPECIMEN_TESTS", "SYMMETRIC_SHAPES", "MESH_FILE_KEYS", "parse_specimen"]


@dataclass(frozen=True)
class _Sized:
    """A specimen given by ``size`` (mm), loaded along its first dimension (x)."""

    @property
    def length(self) -> float:
        return self.size[0]  # type: ignore[attr-defined]

    @property
    def max_dimension(self) -> float:
        return max(self.size)  # type: ignore[attr-defined]


@dataclass(frozen=True)
class BlockSpecimen(_Sized):
    shape: str
    size: tuple[float, float, float]  # mm: length (x, loading axis), width (y), thickness (z)


@dataclass(frozen=True)
class DogboneSpecimen:
    shape: str
    dimensions: DogboneDimensions  # mm; dimensions.standard names the source ("" if explicit)

    @property
    def length(self) -> float:
        return self.dimensions.overall_length

    @property
    def max_dimension(self) -> float:
        return self.dimensions.overall_length


@dataclass(frozen=True)
class SheetSpecimen(_Sized):
    """A thin sheet in the x-y plane, meshed in 2D (cells tri | quad) and solved in plane stress
    (P₃₃ = 0, the thickness follows the material) or plane strain (thickness held)."""

    shape: str
    size: tuple[float, float]  # mm: length (x, loading axis), width (y)
    thickness: float  # mm, through z
    plane: str = "stress"  # "stress" | "strain"
    cells = ("tri", "quad")  # 2D cells; the first is the default mesh.cell


@dataclass(frozen=True)
class CruciformSpecimen:
    shape: str
    dimensions: CruciformDimensions  # mm

    @property
    def length(self) -> float:
        return 2 * self.dimensions.arm_end

    @property
    def max_dimension(self) -> float:
        return 2 * self.dimensions.arm_end


@dataclass(frozen=True)
class MeshFileSpecimen:
    shape: str
    spec: MeshImport  # file (absolute), grip region names, loading axis, marks, area
    data: ImportedMesh = field(compare=False, repr=False)  # the mesh as read at validation

    @property
    def extent(self) -> np.ndarray:
        return self.data.points.max(axis=0) - self.data.points.min(axis=0)

    @property
    def length(self) -> float:
        return float(self.extent[self.spec.axis])

    @property
    def max_dimension(self) -> float:
        return float(self.extent.max())


Specimen = BlockSpecimen | DogboneSpecimen | SheetSpecimen | CruciformSpecimen | MeshFileSpecimen


def _parse_block(t: fields.Table) -> BlockSpecimen:
    size = fields.vector(t.field("size"), t.get("size"), 3, "[length, width, thickness] in mm", gt=0)
    return BlockSpecimen(shape="block", size=size)  # type: ignore[arg-type]


def _parse_dogbone(t: fields.Table) -> DogboneSpecimen:
    """``standard = "<name>"`` loads the shipped dimensions; explicit keys override them."""
    values: dict[str, Any] = {"outer_radius": 0.0}
    standard = t.get("standard", "")
    if "standard" in t.raw:
        data = standard_dimensions(standard) if isinstance(standard, str) else None
        if data is None:
            raise SceneError(f"{t.field('standard')} must be one of {', '.join(standard_names())}; "
                             f"got {fields.show(standard)}{fields.suggest(str(standard), standard_names())}")
        standard = data.pop("standard")
        values.update(data)
    for key in DIMENSION_KEYS:
        if key in t.raw:
            values[key] = t.number(key, ge=0) if key == "outer_radius" else t.number(key, gt=0)
        elif key not in values:
            raise SceneError(f"missing required key {t.field(key)} (or give specimen.standard, one of "
                             f"{', '.join(standard_names())})")
    dims = DogboneDimensions(**values, standard=standard)
    try:
        dims.check()
    except GeometryError as exc:
        raise SceneError(f"specimen.{exc}") from None
    return DogboneSpecimen(shape="dogbone", dimensions=dims)


def _parse_sheet(t: fields.Table) -> SheetSpecimen:
    size = fields.vector(t.field("size"), t.get("size"), 2, "[length, width] in mm (a sheet is 2D; its "
                   "thickness is specimen.thickness)", gt=0)
    thickness = t.number("thickness", gt=0, note=" (mm)")
    return SheetSpecimen(shape="sheet", size=size, thickness=thickness,  # type: ignore[arg-type]
                         plane=t.choice("plane", ("stress", "strain"), default="stress"))


def _parse_cruciform(t: fields.Table) -> CruciformSpecimen:
    """All of arm_width, arm_length, gauge_region, fillet_radius, thickness, grip_length; slits
    optional (slit_count = 0 by default; with slits, slit_width and slit_length are required); a
    thinned centre optional (gauge_thickness with thinning_length)."""
    values: dict[str, Any] = {}
    for key in CRUCIFORM_KEYS[:6]:
        values[key] = t.number(key, ge=0) if key == "fillet_radius" else t.number(key, gt=0)
    values["slit_count"] = t.integer("slit_count", 0, 50, default=0)
    if "gauge_thickness" in t.raw:
        values["gauge_thickness"] = t.number("gauge_thickness", gt=0)
        values["thinning_length"] = t.number("thinning_length", gt=0)
    elif "thinning_length" in t.raw:
        raise SceneError(f"{t.field('thinning_length')} needs specimen.gauge_thickness (a thinned centre)")
    for key in CRUCIFORM_KEYS[7:9]:
        if values["slit_count"]:
            values[key] = t.number(key, gt=0)
        elif key in t.raw:
            raise SceneError(f"{t.field(key)} needs specimen.slit_count >= 1 (the number of slits per arm)")
    dims = CruciformDimensions(**values)
    try:
        dims.check()
    except GeometryError as exc:
        raise SceneError(f"specimen.{exc}") from None
    return CruciformSpecimen(shape="cruciform", dimensions=dims)


_BASE_DIR: ContextVar[Path] = ContextVar("scene_base_dir", default=Path("."))  # resolves specimen.file


_AXES = ("x", "y", "z")


def _marks(t: fields.Table, key: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    v = t.get(key)
    if not isinstance(v, list) or len(v) != 2:
        raise SceneError(f"{t.field(key)} must be two points [[x, y, z], [x, y, z]] in the mesh file's "
                         f"coordinates (mm), got {fields.show(v)}")
    return tuple(fields.vector(f"{t.field(key)}[{i}]", p, 3, "[x, y, z] in mm") for i, p in enumerate(v))  # type: ignore


def _parse_mesh_file(t: fields.Table) -> MeshFileSpecimen:
    """``file`` (.msh or .vtu, relative to the scene file), ``grips = {a = "name", b = "name"}``
    (two named regions of the file), ``axis`` (loading axis of the file, default "x"),
    ``gauge_marks``, ``transverse_marks``, ``thickness_marks`` (two points each) and ``area`` (mm²,
    the section the nominal stress divides by)."""
    name = t.get("file")
    if not isinstance(name, str) or not name:
        raise SceneError(f"{t.field('file')} must be a path to a .msh or .vtu file, got {fields.show(name)}")
    path = Path(name) if Path(name).is_absolute() else _BASE_DIR.get() / name
    try:
        data = read_mesh(path)
    except MeshImportError as exc:
        raise SceneError(f"{exc}") from None
    return mesh_file_specimen(t, path, data)


def mesh_file_specimen(t: fields.Table, path: Path, data: ImportedMesh) -> MeshFileSpecimen:
    """The specimen of a mesh read from ``path`` (a mesh file, or Gmsh's mesh of a CAD file)."""
    grips = t.get("grips")
    if not isinstance(grips, dict) or len(grips) != 2 or not all(isinstance(v, str) for v in grips.values()):
        raise SceneError(f"{t.field('grips')} must be a table of two region names, e.g. {{left = \"grip_left\", "
                         f"right = \"grip_right\"}}, got {fields.show(grips)}")
    for key, region in grips.items():
        if region not in data.regions:
            raise SceneError(f"{t.field('grips')}.{key} = {region!r} is not a region of {path.name}; regions "
                             f"found: {', '.join(data.names) or 'none'}")
    spec = MeshImport(file=path.resolve(), grips=tuple(grips.values()),  # type: ignore[arg-type]
                      axis=_AXES.index(t.choice("axis", _AXES, default="x")),
                      gauge_marks=_marks(t, "gauge_marks"), transverse_marks=_marks(t, "transverse_marks"),
                      thickness_marks=_marks(t, "thickness_marks"), area=t.number("area", gt=0))
    _check_marks_inside(t, spec, data)
    return MeshFileSpecimen(shape="mesh", spec=spec, data=data)


def _parse_cad(t: fields.Table):
    from vlab.scene.cad import parse_cad  # Gmsh is an extra: loaded only for a CAD specimen

    return parse_cad(t, _BASE_DIR.get())


def _check_marks_inside(t: fields.Table, spec: MeshImport, data: ImportedMesh) -> None:
    import skfem

    mesh = (skfem.MeshTet if data.cell == "tet" else skfem.MeshHex)(
        np.ascontiguousarray(data.points.T), np.ascontiguousarray(data.cells.T))
    find = mesh.element_finder()
    for key in ("gauge_marks", "transverse_marks", "thickness_marks"):
        for point in getattr(spec, key):
            try:
                find(*(np.array([c]) for c in point))
            except ValueError:
                raise SceneError(f"{t.field(key)}: point {list(point)} lies outside the mesh of "
                                 f"{spec.file.name} (bounding box {data.points.min(axis=0).tolist()} to "
                                 f"{data.points.max(axis=0).tolist()})") from None


MESH_FILE_KEYS = ("file", "grips", "axis", "gauge_marks", "transverse_marks", "thickness_marks", "area")


# shape -> (allowed keys in [specimen], parser)
SPECIMEN_SHAPES: dict[str, tuple[tuple[str, ...], Callable[[fields.Table], Specimen]]] = {
    "block": (("shape", "size"), _parse_block),
    "dogbone": (("shape", "standard") + DIMENSION_KEYS, _parse_dogbone),
    "sheet": (("shape", "size", "thickness", "plane"), _parse_sheet),
    "cruciform": (("shape",) + CRUCIFORM_KEYS, _parse_cruciform),
    "mesh": (("shape",) + MESH_FILE_KEYS, _parse_mesh_file),
    "cad": (("shape",) + MESH_FILE_KEYS, lambda t: _parse_cad(t)),
}


# shape -> (allowed test kinds, allowed grips); the first grip kind is the default
SPECIMEN_TESTS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "block": (("uniaxial", "biaxial"), ("roller", "clamped")),
    "dogbone": (("uniaxial",), ("clamped",)),
    "sheet": (("uniaxial", "biaxial"), ("roller", "clamped")),
    "cruciform": (("biaxial",), ("clamped",)),
    "mesh": (("uniaxial",), ("clamped",)),
    "cad": (("uniaxial",), ("clamped",)),
}


# shapes whose meshes are built mirror-symmetric and may be reduced by [mesh] symmetry
SYMMETRIC_SHAPES = ("block", "dogbone", "cruciform")


_FINE_MESH_SHAPES = ("dogbone", "cruciform")  # shapes with a [mesh] gauge_size


def parse_specimen(raw: Any) -> Specimen:
    if not isinstance(raw, dict):
        raise SceneError(f"[specimen] must be a table, got {fields.show(raw)}")
    if "shape" not in raw:
        raise SceneError("missing required key specimen.shape")
    shape = fields.choice("specimen.shape", raw["shape"], tuple(SPECIMEN_SHAPES))
    keys, parser = SPECIMEN_SHAPES[shape]
    return parser(fields.Table("specimen", raw, keys))
