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

New specimen shapes: write a frozen dataclass with ``length`` and ``max_dimension``
properties and a parser ``(_Table) -> spec``, and register both in ``SPECIMEN_SHAPES`` (and the
test kinds and grips it allows in ``SPECIMEN_TESTS``).
"""

from __future__ import annotations

import copy
import difflib
import hashlib
import json
import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping

from vlab.geometry.dogbone import DIMENSION_KEYS, DogboneDimensions, GeometryError
from vlab.geometry.standards import standard_dimensions, standard_names
from vlab.moduli import ALIASES, KEYS as MODULI_KEYS, Moduli, ModuliError, from_pair

__all__ = ["SceneError", "Scene", "BlockSpecimen", "DogboneSpecimen", "MeshSpec", "MaterialSpec", "TestSpec",
           "MeasureSpec", "SolverSpec", "load_scene", "parse_scene", "apply_overrides",
           "SPECIMEN_SHAPES", "MODELS"]

SPRING_NETWORK = "spring-network"  # not a material law: mesh edges as springs (vlab.fe.spring_network)
MODELS = ("linear", "stvk", "stvk-volumetric", "neo-hookean", SPRING_NETWORK)
SECTIONS = ("specimen", "mesh", "material", "test", "measure", "solver")
TOP_KEYS = ("name", "description") + SECTIONS
_MODULI_NAMES = MODULI_KEYS + tuple(ALIASES)  # E, nu, lambda, mu, K, M, G, lmbda
_NAME_RE = re.compile(r"[A-Za-z0-9._-]+")
_REQUIRED = object()


class SceneError(ValueError):
    """An invalid scene; the message names the dotted field, the allowed values and the input."""


@dataclass(frozen=True)
class BlockSpecimen:
    shape: str
    size: tuple[float, float, float]  # mm: length (x, loading axis), width (y), thickness (z)

    @property
    def length(self) -> float:
        return self.size[0]

    @property
    def max_dimension(self) -> float:
        return max(self.size)


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


Specimen = BlockSpecimen | DogboneSpecimen


@dataclass(frozen=True)
class MeshSpec:
    size: float  # target element edge, mm
    order: int  # 1 or 2
    cell: str  # "tet" or "hex"
    gauge_size: float | None = None  # element edge over a dogbone's parallel section and fillets
    min_quality: float = 0.15  # smallest acceptable element quality (geometry/quality.py)


@dataclass(frozen=True)
class MaterialSpec:
    model: str
    moduli: Moduli
    given: dict[str, float]  # the two constants as given, canonical names (G -> mu)


@dataclass(frozen=True)
class TestSpec:
    __test__ = False  # not a pytest test class
    kind: str  # "uniaxial" | "biaxial"
    grips: str  # "roller" | "clamped"
    stretch: tuple[float, ...]  # (s,) uniaxial, (sx, sy) biaxial
    steps: int


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
    linear: str = "auto"  # Newton corrections: "auto" | "direct" | "cg-amg" (vlab.fe.iterative)


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

    def content_hash(self) -> str:
        """sha256 hex of the canonical JSON of ``source`` (sorted keys; key order irrelevant)."""
        text = json.dumps(self.source, sort_keys=True, separators=(",", ":"),
                          ensure_ascii=False, default=str)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()


# --- small validators -----------------------------------------------------------------------

def _suggest(word: str, options) -> str:
    close = difflib.get_close_matches(word, list(options), n=1)
    return f" — did you mean {close[0]!r}?" if close else ""


def _show(v: Any) -> str:
    kind = {bool: "boolean", str: "string", list: "array", dict: "table"}.get(type(v))
    if isinstance(v, bool):
        return f"{str(v).lower()} (boolean)"
    return f"{v!r} ({kind})" if kind else f"{v:g}" if isinstance(v, (int, float)) else repr(v)


def _bounds(gt=None, ge=None, lt=None, le=None) -> str:
    ops = ((">", gt), (">=", ge), ("<", lt), ("<=", le))
    return " and ".join(f"{op} {b:g}" for op, b in ops if b is not None)


def _number(field: str, v: Any, *, gt=None, ge=None, lt=None, le=None, note: str = "") -> float:
    rng = _bounds(gt, ge, lt, le)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise SceneError(f"{field} must be a number{' ' + rng if rng else ''}{note}, got {_show(v)}")
    v = float(v)
    if not math.isfinite(v):
        raise SceneError(f"{field} must be a finite number{' ' + rng if rng else ''}, got {v}")
    if ((gt is not None and not v > gt) or (ge is not None and not v >= ge)
            or (lt is not None and not v < lt) or (le is not None and not v <= le)):
        raise SceneError(f"{field} must be {rng}{note}, got {v:g}")
    return v


def _integer(field: str, v: Any, lo: int, hi: int) -> int:
    ok = not isinstance(v, bool) and (isinstance(v, int) or (isinstance(v, float) and v.is_integer()))
    if not ok or not lo <= v <= hi:
        raise SceneError(f"{field} must be an integer {lo}..{hi}, got {_show(v)}")
    return int(v)


def _choice(field: str, v: Any, options: tuple[str, ...]) -> str:
    if v not in options or not isinstance(v, str):
        hint = _suggest(v, options) if isinstance(v, str) else ""
        raise SceneError(f"{field} must be one of {', '.join(options)}; got {_show(v)}{hint}")
    return v


def _vector(field: str, v: Any, n: int, what: str, **bounds) -> tuple[float, ...]:
    if not isinstance(v, list) or len(v) != n:
        raise SceneError(f"{field} must be a list of {n} numbers {what}, got {_show(v)}")
    return tuple(_number(f"{field}[{i}]", x, **bounds) for i, x in enumerate(v))


class _Table:
    """One [section]: rejects unknown keys on creation, then reads fields by name."""

    def __init__(self, section: str, raw: Any, allowed: tuple[str, ...]):
        if not isinstance(raw, dict):
            raise SceneError(f"[{section}] must be a table, got {_show(raw)}")
        for key in raw:
            if key not in allowed:
                raise SceneError(f"unknown key {key!r} in [{section}] (allowed: "
                                 f"{', '.join(allowed)}){_suggest(key, allowed)}")
        self.section, self.raw = section, raw

    def field(self, key: str) -> str:
        return f"{self.section}.{key}"

    def get(self, key: str, default: Any = _REQUIRED) -> Any:
        if key not in self.raw and default is _REQUIRED:
            raise SceneError(f"missing required key {self.field(key)}")
        return self.raw.get(key, default)

    def number(self, key: str, default: Any = _REQUIRED, **bounds) -> float:
        return self.get(key, default) if key not in self.raw else _number(
            self.field(key), self.raw[key], **bounds)

    def integer(self, key: str, lo: int, hi: int, default: Any = _REQUIRED) -> int:
        return _integer(self.field(key), self.get(key, default), lo, hi)

    def choice(self, key: str, options: tuple[str, ...], default: Any = _REQUIRED) -> str:
        return _choice(self.field(key), self.get(key, default), options)


# --- sections ------------------------------------------------------------------------------

def _parse_block(t: _Table) -> BlockSpecimen:
    size = _vector(t.field("size"), t.get("size"), 3, "[length, width, thickness] in mm", gt=0)
    return BlockSpecimen(shape="block", size=size)  # type: ignore[arg-type]


def _parse_dogbone(t: _Table) -> DogboneSpecimen:
    """``standard = "<name>"`` loads the shipped dimensions; explicit keys override them."""
    values: dict[str, Any] = {"outer_radius": 0.0}
    standard = t.get("standard", "")
    if "standard" in t.raw:
        data = standard_dimensions(standard) if isinstance(standard, str) else None
        if data is None:
            raise SceneError(f"{t.field('standard')} must be one of {', '.join(standard_names())}; "
                             f"got {_show(standard)}{_suggest(str(standard), standard_names())}")
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


# shape -> (allowed keys in [specimen], parser)
SPECIMEN_SHAPES: dict[str, tuple[tuple[str, ...], Callable[[_Table], Specimen]]] = {
    "block": (("shape", "size"), _parse_block),
    "dogbone": (("shape", "standard") + DIMENSION_KEYS, _parse_dogbone),
}
# shape -> (allowed test kinds, allowed grips); the first grip kind is the default
SPECIMEN_TESTS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "block": (("uniaxial", "biaxial"), ("roller", "clamped")),
    "dogbone": (("uniaxial",), ("clamped",)),
}


def _parse_specimen(raw: Any) -> Specimen:
    if not isinstance(raw, dict):
        raise SceneError(f"[specimen] must be a table, got {_show(raw)}")
    if "shape" not in raw:
        raise SceneError("missing required key specimen.shape")
    shape = _choice("specimen.shape", raw["shape"], tuple(SPECIMEN_SHAPES))
    keys, parser = SPECIMEN_SHAPES[shape]
    return parser(_Table("specimen", raw, keys))


def _parse_mesh(raw: Any, specimen: Specimen) -> MeshSpec:
    t = _Table("mesh", raw, ("size", "order", "cell", "gauge_size", "min_quality"))
    size = t.number("size", gt=0, le=specimen.max_dimension, note=" (the largest specimen dimension)")
    gauge_size = t.number("gauge_size", default=None, gt=0, le=size, note=" (mesh.size)")
    if gauge_size is not None and specimen.shape != "dogbone":
        raise SceneError(f"{t.field('gauge_size')} applies to specimen.shape = 'dogbone' only, "
                         f"not {specimen.shape!r}")
    return MeshSpec(size=size, order=t.integer("order", 1, 2, default=1),
                    cell=t.choice("cell", ("tet", "hex"), default="tet"), gauge_size=gauge_size,
                    min_quality=t.number("min_quality", default=0.15, gt=0, lt=1))


def _parse_material(raw: Any) -> MaterialSpec:
    t = _Table("material", raw, ("model", "root") + _MODULI_NAMES)
    model = t.choice("model", MODELS)
    root = t.choice("root", ("plus", "minus"), default="plus")
    values = {k: t.number(k) for k in _MODULI_NAMES if k in t.raw}
    try:
        moduli = from_pair(values, root=root)
    except ModuliError as exc:
        msg = str(exc)
        raise SceneError(msg if "material." in msg
                         else f"[material]: {msg}") from None
    given = {ALIASES.get(k, k): v for k, v in values.items()}
    return MaterialSpec(model=model, moduli=moduli, given=given)


def _stretch_value(field: str, v: Any) -> float:
    v = _number(field, v, note=" (allowed 0.2..10)")
    if v <= 0:
        raise SceneError(f"{field} must be > 0 (allowed 0.2..10), got {v:g}")
    if not 0.2 <= v <= 10:
        raise SceneError(f"{field} must be in the allowed range 0.2..10, got {v:g}")
    return v


def _parse_test(raw: Any, shape: str = "block") -> TestSpec:
    t = _Table("test", raw, ("kind", "grips", "stretch", "steps"))
    kinds, grip_kinds = SPECIMEN_TESTS[shape]
    kind = t.choice("kind", ("uniaxial", "biaxial"))
    if kind not in kinds:
        raise SceneError(f"{t.field('kind')} must be one of {', '.join(kinds)} for specimen.shape = "
                         f"{shape!r}, got {kind!r}")
    grips = t.choice("grips", ("roller", "clamped"), default=grip_kinds[0])
    if grips not in grip_kinds:
        raise SceneError(f"{t.field('grips')} must be one of {', '.join(grip_kinds)} for specimen.shape = "
                         f"{shape!r}, got {grips!r}")
    field, v = t.field("stretch"), t.get("stretch")
    if kind == "uniaxial":
        if isinstance(v, list):
            raise SceneError(f"{field} must be a single number for kind = 'uniaxial', got {_show(v)}")
        stretch: tuple[float, ...] = (_stretch_value(field, v),)
    else:
        if not isinstance(v, list) or len(v) != 2:
            raise SceneError(f"{field} must be a list [sx, sy] of 2 numbers for kind = 'biaxial' "
                             f"(each 0.2..10), got {_show(v)}")
        stretch = tuple(_stretch_value(f"{field}[{i}]", x) for i, x in enumerate(v))
    if all(s == 1.0 for s in stretch):
        raise SceneError(f"{field} must not be 1 everywhere (a stretch of 1 applies no load), "
                         f"got {_show(v)}")
    return TestSpec(kind=kind, grips=grips, stretch=stretch,
                    steps=t.integer("steps", 1, 10000, default=10))


def _parse_measure(raw: Any, specimen: Specimen) -> MeasureSpec:
    t = _Table("measure", raw, ("modulus_window", "gauge_length", "fit", "modulus_points"))
    field = t.field("modulus_window")
    window = (0.0005, 0.0025)
    if "modulus_window" in t.raw:
        window = _vector(field, t.raw["modulus_window"], 2, "[a, b]", ge=0, le=0.05)
        if not window[0] < window[1]:
            raise SceneError(f"{field} must satisfy 0 <= a < b <= 0.05, got {list(window)}")
    gauge = t.number("gauge_length", default=None, gt=0, lt=specimen.length,
                     note=" (the specimen length)")
    return MeasureSpec(modulus_window=window, gauge_length=gauge,  # type: ignore[arg-type]
                       fit=t.choice("fit", ("regression", "chord"), default="regression"),
                       modulus_points=t.integer("modulus_points", 0, 100, default=9))


def _parse_solver(raw: Any) -> SolverSpec:
    t = _Table("solver", raw, ("rtol", "max_iterations", "max_cutbacks", "linear"))
    return SolverSpec(rtol=t.number("rtol", default=1e-8, ge=1e-14, le=1e-2),
                      max_iterations=t.integer("max_iterations", 1, 200, default=25),
                      max_cutbacks=t.integer("max_cutbacks", 0, 30, default=8),
                      linear=t.choice("linear", ("auto", "direct", "cg-amg"), default="auto"))


def _parse(data: Mapping[str, Any]) -> Scene:
    if not isinstance(data, Mapping):
        raise SceneError(f"a scene must be a table of sections, got {_show(data)}")
    for key, val in data.items():
        if key not in TOP_KEYS:
            what = f"section [{key}]" if isinstance(val, dict) else f"top-level key {key!r}"
            raise SceneError(f"unknown {what} (allowed: {', '.join(TOP_KEYS)})"
                             f"{_suggest(key, TOP_KEYS)}")
    for section in ("specimen", "mesh", "material", "test"):
        if section not in data:
            raise SceneError(f"missing required section [{section}]")
    if "name" not in data:
        raise SceneError("missing required key name")
    name = data["name"]
    if not isinstance(name, str) or not _NAME_RE.fullmatch(name) or set(name) == {"."}:
        raise SceneError(f"name must match [A-Za-z0-9._-]+ (it names the report folder) and not "
                         f"be only dots, got {_show(name)}")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise SceneError(f"description must be a string, got {_show(description)}")
    specimen = _parse_specimen(data["specimen"])
    mesh, material = _parse_mesh(data["mesh"], specimen), _parse_material(data["material"])
    if material.model == SPRING_NETWORK and mesh.order != 1:
        raise SceneError(f"material.model {SPRING_NETWORK!r} joins mesh vertices by springs and needs "
                         f"mesh.order = 1, got {mesh.order}")
    return Scene(name=name, description=description, specimen=specimen,
                 mesh=mesh, material=material,
                 test=_parse_test(data["test"], specimen.shape),
                 measure=_parse_measure(data.get("measure", {}), specimen),
                 solver=_parse_solver(data.get("solver", {})),
                 source=copy.deepcopy(dict(data)))


# --- public entry points -------------------------------------------------------------------

def parse_scene(data: dict, origin: str = "<scene>") -> Scene:
    """Validate a parsed scene dict; errors are ``SceneError("<origin>: <message>")``."""
    try:
        return _parse(data)
    except SceneError as exc:
        raise SceneError(f"{origin}: {exc}") from None


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
    return parse_scene(data, origin=str(path))


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
                             f"(allowed: {', '.join(SECTIONS)}){_suggest(head, SECTIONS)}")
        else:
            raise SceneError(f"override {dotted!r}: expected 'section.key' or one of "
                             f"name, description{_suggest(dotted, TOP_KEYS)}")
    return out
