"""Scene files (TOML) -> validated, frozen dataclasses.

A scene describes one virtual test: specimen, mesh, material, loading, measurement, solver.
Required: ``name``, [specimen] shape+size, [mesh] size, [material] model + exactly two elastic
constants, [test] kind+stretch. Defaults: mesh.order = 1, mesh.cell = "tet", material.root =
"plus", test.grips = "roller", test.steps = 10, [measure] modulus_window = [0.0005, 0.0025],
gauge_length = None, fit = "regression", modulus_points = 9; [solver] rtol = 1e-8, max_iterations = 25,
max_cutbacks = 8. Unknown sections and keys are errors. Every :class:`SceneError` names the
dotted field, the allowed values and what was got.

Dogbones: ``[specimen] shape = "dogbone"`` with ``standard = "<name>"`` (dimensions shipped in
vlab/data/standards/) and/or the explicit keys of ``DIMENSION_KEYS`` (explicit keys win); tested
uniaxially between clamped grips. ``[mesh] gauge_size`` refines a dogbone's parallel section and
fillets; ``[mesh] min_quality`` (default 0.15) is the worst element quality a run accepts.
``[mesh] formulation`` = "displacement" (default) or "mixed" (locking-free for ν → ½; needs a
model with a ``split`` in the model registry, and hexes or order-2 tets).

Sheets: ``[specimen] shape = "sheet"`` with ``size = [length, width]``, ``thickness`` (mm) and
``plane = "stress"`` (default) or ``"strain"``; meshed in 2D with ``mesh.cell = "tri" | "quad"``.

Cruciforms: ``[specimen] shape = "cruciform"`` with arm_width, arm_length, gauge_region,
fillet_radius, thickness, grip_length and optional slit_count, slit_width, slit_length; tested
biaxially between four clamped grips. ``[mesh] symmetry = "none" | "half" | "quarter" | "eighth"``
meshes only that part of a block, dogbone or cruciform (geometry/symmetry.py).

New specimen shapes: write a frozen dataclass with ``length`` and ``max_dimension``
properties and a parser ``(fields.Table) -> spec``, and register both in ``SPECIMEN_SHAPES`` (and the
test kinds and grips it allows in ``SPECIMEN_TESTS``).
"""

from __future__ import annotations

import copy
import hashlib
import json
import re
import tomllib
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.cruciform import CRUCIFORM_KEYS, CruciformDimensions
from vlab.geometry.dogbone import DIMENSION_KEYS, DogboneDimensions, GeometryError
from vlab.geometry.imported import ImportedMesh, MeshImport, MeshImportError, read_mesh
from vlab.geometry.symmetry import SYMMETRY_LEVELS
from vlab.geometry.standards import standard_dimensions, standard_names
from vlab.loading.protocol import HOLDS, PROTOCOLS, ProtocolSpec
from vlab.materials.card import MaterialSpec, check_path, parse_material
from vlab.materials.registry import MODELS as MODEL_REGISTRY

__all__ = ["SceneError", "Scene", "BlockSpecimen", "DogboneSpecimen", "SheetSpecimen", "CruciformSpecimen", "MeshSpec", "MaterialSpec", "TestSpec",
           "MeasureSpec", "SolverSpec", "load_scene", "parse_scene", "apply_overrides",
           "SPECIMEN_SHAPES", "MODELS"]

SPRING_NETWORK = "spring-network"  # not a material law: mesh edges as springs (vlab.fe.spring_network)
MODELS = tuple(MODEL_REGISTRY)  # the model registry's names (vlab.materials.registry)
FORMULATIONS = ("displacement", "mixed")  # mesh.formulation
SECTIONS = ("specimen", "mesh", "material", "test", "measure", "solver", "effects", "compare")
TOP_KEYS = ("name", "description") + SECTIONS
_NAME_RE = re.compile(r"[A-Za-z0-9._-]+")
PROTOCOL_KEYS = ("protocol", "amplitudes", "min_stretch", "strain_rate", "ramp_time", "hold_time",
                 "hold_steps", "force")


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


@dataclass(frozen=True)
class MeshSpec:
    size: float  # target element edge, mm
    order: int  # 1 or 2
    cell: str  # "tet" or "hex"; "tri" or "quad" for a sheet
    gauge_size: float | None = None  # element edge over a dogbone's parallel section and fillets
    min_quality: float = 0.15  # smallest acceptable element quality (geometry/quality.py)
    formulation: str = "displacement"  # or "mixed": condensed θ/p per element (vlab/fe/mixed.py)
    symmetry: str = "none"  # none | half | quarter | eighth (geometry/symmetry.py)


@dataclass(frozen=True)
class TestSpec:
    __test__ = False  # not a pytest test class
    kind: str  # "uniaxial" | "biaxial"
    grips: str  # "roller" | "clamped"
    stretch: tuple[float, ...]  # (s,) uniaxial, (sx, sy) biaxial
    steps: int
    protocol: ProtocolSpec = ProtocolSpec()  # vlab.loading.protocol: monotonic unless given
    imperfection: float | None = None  # buckling-mode imperfection, amplitude / thickness


@dataclass(frozen=True)
class MeasureSpec:
    modulus_window: tuple[float, float]  # |strain| window for the E and nu fits
    gauge_length: float | None  # mm; None = decided by the extensometer (half the length)
    fit: str  # "regression" | "chord"
    modulus_points: int = 9  # extra readings inserted in the modulus window (0 = none)


@dataclass(frozen=True)
class SolverSpec:
    rtol: float
    max_iterations: int
    max_cutbacks: int
    eigenvalues: bool = False  # lowest eigenvalue of K_ff at every converged state
    linear: str = "auto"  # Newton corrections: "auto" | "direct" | "cg-amg" (vlab.fe.iterative)
    newton: str = "reuse"  # "reuse": keep a factor while chord steps contract; "exact": refactorize


@dataclass(frozen=True)
class Scene:
    name: str
    description: str
    specimen: Specimen
    mesh: MeshSpec
    material: MaterialSpec
    test: TestSpec
    measure: MeasureSpec
    solver: SolverSpec
    source: dict  # the raw parsed TOML, for provenance
    effects: tuple = ()  # validated effect specs (vlab.effects), each with a ``name``; () = elastic

    def effect(self, name: str):
        """The spec of the declared effect ``name``, or None."""
        return next((e for e in self.effects if e.name == name), None)
    base_dir: str = "."  # where relative paths in the scene (specimen.file) are taken from

    def content_hash(self) -> str:
        """sha256 hex of the canonical JSON of ``source`` (sorted keys; key order irrelevant)."""
        text = json.dumps(self.source, sort_keys=True, separators=(",", ":"),
                          ensure_ascii=False, default=str)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()


# --- sections ------------------------------------------------------------------------------

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
}
# shape -> (allowed test kinds, allowed grips); the first grip kind is the default
SPECIMEN_TESTS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "block": (("uniaxial", "biaxial"), ("roller", "clamped")),
    "dogbone": (("uniaxial",), ("clamped",)),
    "sheet": (("uniaxial", "biaxial"), ("roller", "clamped")),
    "cruciform": (("biaxial",), ("clamped",)),
    "mesh": (("uniaxial",), ("clamped",)),
}
# shapes whose meshes are built mirror-symmetric and may be reduced by [mesh] symmetry
SYMMETRIC_SHAPES = ("block", "dogbone", "cruciform")
_FINE_MESH_SHAPES = ("dogbone", "cruciform")  # shapes with a [mesh] gauge_size


def _parse_specimen(raw: Any) -> Specimen:
    if not isinstance(raw, dict):
        raise SceneError(f"[specimen] must be a table, got {fields.show(raw)}")
    if "shape" not in raw:
        raise SceneError("missing required key specimen.shape")
    shape = fields.choice("specimen.shape", raw["shape"], tuple(SPECIMEN_SHAPES))
    keys, parser = SPECIMEN_SHAPES[shape]
    return parser(fields.Table("specimen", raw, keys))


def _parse_mesh(raw: Any, specimen: Specimen) -> MeshSpec:
    t = fields.Table("mesh", raw, ("size", "order", "cell", "gauge_size", "min_quality", "symmetry", "formulation"))
    if specimen.shape == "mesh":
        return _parse_mesh_of_file(t, specimen)
    size = t.number("size", gt=0, le=specimen.max_dimension, note=" (the largest specimen dimension)")
    gauge_size = t.number("gauge_size", default=None, gt=0, le=size, note=" (mesh.size)")
    if gauge_size is not None and specimen.shape not in _FINE_MESH_SHAPES:
        raise SceneError(f"{t.field('gauge_size')} applies to specimen.shape = "
                         f"{' or '.join(map(repr, _FINE_MESH_SHAPES))} only, not {specimen.shape!r}")
    symmetry = t.choice("symmetry", SYMMETRY_LEVELS, default="none")
    if symmetry != "none" and specimen.shape not in SYMMETRIC_SHAPES:
        raise SceneError(f"{t.field('symmetry')} must be 'none' for specimen.shape = {specimen.shape!r} "
                         f"(symmetry reduction is for {', '.join(SYMMETRIC_SHAPES)}), got {symmetry!r}")
    cells = getattr(specimen, "cells", ("tet", "hex"))  # a specimen's own cells (2D: tri, quad)
    return MeshSpec(size=size, order=t.integer("order", 1, 2, default=1),
                    cell=t.choice("cell", cells, default=cells[0]), gauge_size=gauge_size,
                    min_quality=t.number("min_quality", default=0.15, gt=0, lt=1), symmetry=symmetry,
                    formulation=t.choice("formulation", FORMULATIONS, default="displacement"))


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


def _check_formulation(mesh: MeshSpec, model: str) -> None:
    """The mixed formulation needs a split law and an element pair that does not lock."""
    if mesh.formulation != "mixed":
        return
    if MODEL_REGISTRY[model].split is None:
        split = ", ".join(n for n, m in MODEL_REGISTRY.items() if m.split is not None)
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


def _parse_material(raw: Any) -> MaterialSpec:
    """[material]: the card grammar of the model registry (vlab.materials.card)."""
    return parse_material(raw, "material")


def _parse_compare(raw: Any) -> dict[str, MaterialSpec]:
    """[compare.<label>] tables: one material card each, run side by side by ``vlab compare``."""
    if not isinstance(raw, dict):
        raise SceneError(f"[compare] must be a table of material cards [compare.<label>], got {fields.show(raw)}")
    cards = {}
    for label, card in raw.items():
        if not _NAME_RE.fullmatch(label):
            raise SceneError(f"compare.{label}: a label must match [A-Za-z0-9._-]+ (it names a report folder)")
        cards[label] = parse_material(card, f"compare.{label}")
    return cards


def _stretch_value(field: str, v: Any) -> float:
    v = fields.number(field, v, note=" (allowed 0.2..10)")
    if v <= 0:
        raise SceneError(f"{field} must be > 0 (allowed 0.2..10), got {v:g}")
    if not 0.2 <= v <= 10:
        raise SceneError(f"{field} must be in the allowed range 0.2..10, got {v:g}")
    return v


def _parse_test(raw: Any, shape: str = "block") -> TestSpec:
    t = fields.Table("test", raw, ("kind", "grips", "stretch", "steps", "imperfection") + PROTOCOL_KEYS)
    kinds, grip_kinds = SPECIMEN_TESTS[shape]
    kind = t.choice("kind", ("uniaxial", "biaxial"))
    if kind not in kinds:
        raise SceneError(f"{t.field('kind')} must be one of {', '.join(kinds)} for specimen.shape = "
                         f"{shape!r}, got {kind!r}")
    grips = t.choice("grips", ("roller", "clamped"), default=grip_kinds[0])
    if grips not in grip_kinds:
        raise SceneError(f"{t.field('grips')} must be one of {', '.join(grip_kinds)} for specimen.shape = "
                         f"{shape!r}, got {grips!r}")
    protocol_name = t.choice("protocol", PROTOCOLS, default="monotonic")
    field, v = t.field("stretch"), t.get("stretch", None if protocol_name == "cyclic" else fields.REQUIRED)
    if protocol_name == "cyclic":
        amplitudes = _amplitudes(t, kind)
        if v is not None:
            raise SceneError(f"{field} is not used with test.protocol = 'cyclic' (the largest of "
                             f"test.amplitudes is the peak stretch); remove it, got {fields.show(v)}")
        v = amplitudes[-1]
    if kind == "uniaxial":
        if isinstance(v, list):
            raise SceneError(f"{field} must be a single number for kind = 'uniaxial', got {fields.show(v)}")
        stretch: tuple[float, ...] = (_stretch_value(field, v),)
    else:
        if not isinstance(v, list) or len(v) != 2:
            raise SceneError(f"{field} must be a list [sx, sy] of 2 numbers for kind = 'biaxial' "
                             f"(each 0.2..10), got {fields.show(v)}")
        stretch = tuple(_stretch_value(f"{field}[{i}]", x) for i, x in enumerate(v))
    if all(s == 1.0 for s in stretch):
        raise SceneError(f"{field} must not be 1 everywhere (a stretch of 1 applies no load), "
                         f"got {fields.show(v)}")
    return TestSpec(kind=kind, grips=grips, stretch=stretch,
                    steps=t.integer("steps", 1, 10000, default=10),
                    protocol=_parse_protocol(t, protocol_name, stretch),
                    imperfection=_imperfection(t, stretch))


def _amplitudes(t: fields.Table, kind: str) -> tuple[float, ...]:
    field, v = t.field("amplitudes"), t.get("amplitudes")
    if kind != "uniaxial":
        raise SceneError(f"test.protocol = 'cyclic' needs test.kind = 'uniaxial', got {kind!r}")
    if not isinstance(v, list) or not 1 <= len(v) <= 50:
        raise SceneError(f"{field} must be a list of 1..50 peak grip stretches, got {fields.show(v)}")
    amps = tuple(_stretch_value(f"{field}[{i}]", x) for i, x in enumerate(v))
    side = [a > 1.0 for a in amps]
    growing = all(abs(b - 1.0) > abs(a - 1.0) for a, b in zip(amps, amps[1:]))
    if 1.0 in amps or len(set(side)) > 1 or not growing:
        raise SceneError(f"{field} must move away from 1 on one side with every cycle (rising "
                         f"amplitudes, all > 1 or all < 1), got {list(amps)}")
    return amps


def _parse_protocol(t: fields.Table, name: str, stretch: tuple[float, ...]) -> ProtocolSpec:
    """The [test] protocol keys: each allowed only for the protocols that use it."""
    uses = {"amplitudes": ("cyclic",), "min_stretch": ("cyclic",), "hold_time": HOLDS,
            "hold_steps": HOLDS, "force": ("creep",)}
    for key, protocols in uses.items():
        if key in t.raw and name not in protocols:
            raise SceneError(f"{t.field(key)} applies to test.protocol = {' or '.join(map(repr, protocols))} "
                             f"only, not {name!r}")
    if "strain_rate" in t.raw and "ramp_time" in t.raw:
        raise SceneError("give one of test.strain_rate (1/s) or test.ramp_time (s), not both")
    if name in HOLDS and not ("strain_rate" in t.raw or "ramp_time" in t.raw):
        raise SceneError(f"test.protocol = {name!r} holds for a time: give test.strain_rate (1/s) or "
                         f"test.ramp_time (s) of the ramp, and test.hold_time (s)")
    min_stretch = 1.0
    if name == "cyclic" and "min_stretch" in t.raw:
        top = stretch[0]
        lo, hi = (1.0, None) if top > 1 else (None, 1.0)
        min_stretch = t.number("min_stretch", ge=lo, le=hi, note=" (between 1 and the first amplitude)")
        first = t.raw["amplitudes"][0]
        if abs(min_stretch - 1.0) >= abs(first - 1.0):
            raise SceneError(f"{t.field('min_stretch')} must lie between 1 and the first amplitude "
                             f"{first:g}, got {min_stretch:g}")
    return ProtocolSpec(
        name=name, amplitudes=tuple(t.raw.get("amplitudes", ())) if name == "cyclic" else (),
        min_stretch=min_stretch,
        strain_rate=t.number("strain_rate", default=None, gt=0, le=1e4, note=" 1/s"),
        ramp_time=t.number("ramp_time", default=None, gt=0, le=1e9, note=" s"),
        hold_time=t.number("hold_time", gt=0, le=1e9, note=" s") if name in HOLDS else 0.0,
        hold_steps=t.integer("hold_steps", 1, 10000, default=20),
        force=_creep_force(t, stretch) if name == "creep" else None)


def _creep_force(t: fields.Table, stretch: tuple[float, ...]) -> float | None:
    """test.force (N): the creep load, ramped under force control over test.ramp_time, then held.
    Its sign follows test.stretch (which then only gives the direction and scale of the grip
    travel): > 0 in tension (stretch > 1), < 0 in compression."""
    if "force" not in t.raw:
        return None
    if "ramp_time" not in t.raw:
        raise SceneError(f"{t.field('force')} is ramped under force control: give test.ramp_time (s), "
                         "the time to reach it (test.strain_rate sets a grip speed, not a load rate)")
    if len(stretch) != 1:
        raise SceneError(f"{t.field('force')} needs test.kind = 'uniaxial'")
    if stretch[0] > 1.0:
        return t.number("force", gt=0, le=1e9, note=" N, tension as test.stretch > 1")
    return t.number("force", ge=-1e9, lt=0, note=" N, compression as test.stretch < 1")


def _imperfection(t: fields.Table, stretch: tuple[float, ...]) -> float | None:
    """``[test] imperfection``: amplitude of the buckling-mode imperfection / specimen thickness,
    0 < a <= 0.5, for uniaxial compression only (a tension test has no buckling mode)."""
    if "imperfection" not in t.raw:
        return None
    value = t.number("imperfection", gt=0, le=0.5, note=" (amplitude / specimen thickness)")
    if len(stretch) != 1 or stretch[0] >= 1.0:
        raise SceneError(f"{t.field('imperfection')} applies to uniaxial compression (test.stretch < 1), "
                         f"got test.stretch = {list(stretch)}")
    return value


def _parse_measure(raw: Any, specimen: Specimen) -> MeasureSpec:
    t = fields.Table("measure", raw, ("modulus_window", "gauge_length", "fit", "modulus_points"))
    field = t.field("modulus_window")
    window = (0.0005, 0.0025)
    if "modulus_window" in t.raw:
        window = fields.vector(field, t.raw["modulus_window"], 2, "[a, b]", ge=0, le=0.05)
        if not window[0] < window[1]:
            raise SceneError(f"{field} must satisfy 0 <= a < b <= 0.05, got {list(window)}")
    gauge = t.number("gauge_length", default=None, gt=0, lt=specimen.length,
                     note=" (the specimen length)")
    if gauge is not None and specimen.shape == "cruciform" and gauge > specimen.dimensions.gauge_region:
        raise SceneError(f"{t.field('gauge_length')} must be in (0, specimen.gauge_region = "
                         f"{specimen.dimensions.gauge_region:g}] mm for a cruciform (the extensometers sit in "
                         f"the gauge region), got {gauge:g}")
    return MeasureSpec(modulus_window=window, gauge_length=gauge,  # type: ignore[arg-type]
                       fit=t.choice("fit", ("regression", "chord"), default="regression"),
                       modulus_points=t.integer("modulus_points", 0, 100, default=9))


def _parse_solver(raw: Any) -> SolverSpec:
    t = fields.Table("solver", raw, ("rtol", "max_iterations", "max_cutbacks", "eigenvalues", "linear", "newton"))
    eigenvalues = t.get("eigenvalues", False)
    if not isinstance(eigenvalues, bool):
        raise SceneError(f"{t.field('eigenvalues')} must be true or false, got {fields.show(eigenvalues)}")
    return SolverSpec(rtol=t.number("rtol", default=1e-8, ge=1e-14, le=1e-2),
                      max_iterations=t.integer("max_iterations", 1, 200, default=25),
                      max_cutbacks=t.integer("max_cutbacks", 0, 30, default=8), eigenvalues=eigenvalues,
                      linear=t.choice("linear", ("auto", "direct", "cg-amg"), default="auto"),
                      newton=t.choice("newton", ("reuse", "exact"), default="reuse"))


def _check_symmetry(mesh: MeshSpec, test: TestSpec, specimen: Specimen) -> None:
    """Refuse a symmetry reduction of a set-up that is not symmetric: a block pulled biaxially
    between clamped grips, one of each pair fixed, shifts the y grips against the x clamps (which
    hold u_y = 0), so its solution is not mirror-symmetric. (Roller grips are: their 3-2-1
    supports pin rigid motions only and give way to the symmetry planes; dogbones and centred
    cruciforms are.)"""
    if (mesh.symmetry != "none" and specimen.shape == "block" and test.kind == "biaxial"
            and test.grips == "clamped"):
        raise SceneError(f"mesh.symmetry must be 'none' for a biaxial block between clamped grips (one "
                         f"grip per axis holds, so the set-up is not mirror-symmetric), got {mesh.symmetry!r}; "
                         f"use test.grips = 'roller' or a cruciform")


def _parse(data: Mapping[str, Any]) -> Scene:
    if not isinstance(data, Mapping):
        raise SceneError(f"a scene must be a table of sections, got {fields.show(data)}")
    for key, val in data.items():
        if key not in TOP_KEYS:
            what = f"section [{key}]" if isinstance(val, dict) else f"top-level key {key!r}"
            raise SceneError(f"unknown {what} (allowed: {', '.join(TOP_KEYS)})"
                             f"{fields.suggest(key, TOP_KEYS)}")
    for section in ("specimen", "mesh", "material", "test"):
        if section not in data:
            raise SceneError(f"missing required section [{section}]")
    if "name" not in data:
        raise SceneError("missing required key name")
    name = data["name"]
    if not isinstance(name, str) or not _NAME_RE.fullmatch(name) or set(name) == {"."}:
        raise SceneError(f"name must match [A-Za-z0-9._-]+ (it names the report folder) and not "
                         f"be only dots, got {fields.show(name)}")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise SceneError(f"description must be a string, got {fields.show(description)}")
    specimen = _parse_specimen(data["specimen"])
    mesh, material = _parse_mesh(data["mesh"], specimen), _parse_material(data["material"])
    _check_formulation(mesh, material.model)
    _parse_compare(data.get("compare", {}))
    if not MODEL_REGISTRY[material.model].continuum and mesh.order != 1:
        raise SceneError(f"material.model {SPRING_NETWORK!r} joins mesh vertices by springs and needs "
                         f"mesh.order = 1, got {mesh.order}")
    if not MODEL_REGISTRY[material.model].continuum and specimen.shape == "sheet":
        raise SceneError(f"material.model {SPRING_NETWORK!r} is a 3D network of mesh edges; "
                         f"specimen.shape = 'sheet' needs a continuum model (not {SPRING_NETWORK!r})")
    test = _parse_test(data["test"], specimen.shape)
    if MODEL_REGISTRY[material.model].continuum:
        check_path(material, [test.stretch])  # the test's extreme grip stretch
    _check_symmetry(mesh, test, specimen)
    _check_effects_scope(data.get("effects", {}), specimen.shape, mesh, material.model)
    return Scene(name=name, description=description, specimen=specimen,
                 mesh=mesh, material=material, test=test,
                 measure=_parse_measure(data.get("measure", {}), specimen),
                 solver=_parse_solver(data.get("solver", {})),
                 source=copy.deepcopy(dict(data)), base_dir=str(_BASE_DIR.get()),
                 effects=_parse_effects(data.get("effects", {}), material, test))


def _check_effects_scope(raw: Any, shape: str, mesh: MeshSpec, model: str) -> None:
    """Effects run on displacement-formulation 3D continua only: say so instead of ignoring them."""
    if not raw or not isinstance(raw, dict):
        return
    name = f"effects.{next(iter(raw))}"
    if not MODEL_REGISTRY[model].continuum:
        raise SceneError(f"{name}: material.model {model!r} is a network of springs without "
                         f"effects; use a continuum model with [effects]")
    if shape == "sheet":
        raise SceneError(f"{name}: [effects] are not available on specimen.shape = 'sheet' (2D) in "
                         f"this build; use a block or a dogbone")
    if mesh.formulation == "mixed":
        raise SceneError(f"{name}: [effects] need mesh.formulation = 'displacement' in this build "
                         f"(the mixed formulation wraps split elastic laws only)")


def _parse_effects(raw: Any, material: MaterialSpec, test: TestSpec) -> tuple:
    """[effects.<name>] tables -> effect specs, validated by the registry (vlab.effects)."""
    from vlab.effects import EFFECTS  # lazy: the effect parsers use this module's fields.Table

    if not isinstance(raw, dict):
        raise SceneError(f"[effects] must be a table of effects, got {fields.show(raw)}")
    specs = []
    for name, table in raw.items():
        if name not in EFFECTS:
            raise SceneError(f"unknown effect effects.{name} (allowed: {', '.join(EFFECTS)})"
                             f"{fields.suggest(name, EFFECTS)}")
        effect = EFFECTS[name]
        spec = effect.parse(fields.Table(f"effects.{name}", table, effect.keys), material, test)
        if effect.protocols is not None and test.protocol.name not in effect.protocols:
            raise SceneError(f"effects.{name} cannot show with test.protocol = {test.protocol.name!r}: "
                             f"use one of {', '.join(effect.protocols)}")
        if effect.timed and not test.protocol.timed:
            raise SceneError(f"effects.{name} makes the test rate-dependent: give test.strain_rate "
                             f"(1/s) or test.ramp_time (s)")
        specs.append(spec)
    laws = [s.name for s in specs if EFFECTS[s.name].role == "material"]
    if len(laws) > 1:
        raise SceneError(f"effects: one history-dependent law at a time, got {', '.join(laws)}")
    if laws and material.model not in EFFECTS[laws[0]].models:
        raise SceneError(f"effects.{laws[0]} wraps material.model = one of "
                         f"{', '.join(EFFECTS[laws[0]].models)}, got {material.model!r}")
    return tuple(specs)


# --- public entry points -------------------------------------------------------------------

def parse_scene(data: dict, origin: str = "<scene>", base_dir: str | Path | None = None) -> Scene:
    """Validate a parsed scene dict; errors are ``SceneError("<origin>: <message>")``. Relative
    paths in the scene (specimen.file) are taken from ``base_dir`` (default: the current folder)."""
    token = _BASE_DIR.set(Path(base_dir) if base_dir is not None else Path("."))
    try:
        return _parse(data)
    except SceneError as exc:
        raise SceneError(f"{origin}: {exc}") from None
    finally:
        _BASE_DIR.reset(token)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene TOML file; every error message starts with the file name."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise SceneError(f"{path}: cannot read scene file ({exc.strerror or exc})") from None
    except UnicodeDecodeError as exc:
        raise SceneError(f"{path}: scene file is not UTF-8 ({exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: TOML syntax error: {exc}") from None
    return parse_scene(data, origin=str(path), base_dir=path.parent)


def apply_overrides(data: Mapping[str, Any], overrides: Mapping[str, object]) -> dict:
    """Return a deep copy of the raw scene dict with dotted keys set, e.g.
    ``{"material.nu": 0.45, "mesh.size": 2, "name": "run-3"}``. Unknown sections or top-level
    keys raise SceneError; unknown keys inside a section are left to :func:`parse_scene`."""
    out = copy.deepcopy(dict(data))
    for dotted, value in overrides.items():
        parts = dotted.split(".")
        head = parts[0]
        if len(parts) == 1 and head in TOP_KEYS and head not in SECTIONS:
            out[head] = copy.deepcopy(value)
        elif len(parts) == 2 and head in SECTIONS:
            table = out.setdefault(head, {})
            if not isinstance(table, dict):
                raise SceneError(f"override {dotted!r}: [{head}] is not a table")
            table[parts[1]] = copy.deepcopy(value)
        elif len(parts) == 2:
            raise SceneError(f"override {dotted!r}: unknown section [{head}] "
                             f"(allowed: {', '.join(SECTIONS)}){fields.suggest(head, SECTIONS)}")
        else:
            raise SceneError(f"override {dotted!r}: expected 'section.key' or one of "
                             f"name, description{fields.suggest(dotted, TOP_KEYS)}")
    return out
