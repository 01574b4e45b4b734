"""The fit file (TOML), validated like a scene: every error is a SceneError naming the key.

    name = "rubber-a"
    [model]    name (neo-hookean | mooney-rivlin | yeoh | gent | arruda-boyce | ogden; "ogden-3" =
               ogden with terms = 3), terms (ogden, 1..6), incompressible (default true), K (fixed
               bulk modulus, MPa) or fit_K = true, volumetric (quadratic | log | simo-taylor),
               K_over_mu (incompressible only: the card's K / mu0, 10..1e8, default 1000)
    [[data]]   file (resolved against the fit file's folder), kind, columns, stress_measure,
               units, role (fit | validate), weight, name; geometry (the kinds of
               vlab.identify.kinds that need lengths: torsion radius, inflation inner_radius and
               thickness, mm); specimen (an id string: data sets of several specimens of one
               material are fitted per specimen and pooled, vlab.identify.specimens)
    [options]  residual (relative | absolute), starts (1..1000), seed, confidence (0.5..0.999),
               max_evaluations (per start, default 400)
    [fe]       scene (kind = "specimen" or "field"), parameters (the card keys fitted), start, max_solves
    kind = "field": a DIC fields folder instead of a file (vlab.identify.field_data)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table
from vlab.identify.card import INCOMPRESSIBLE_K_RATIO
from vlab.identify.datasets import (COLUMN_KEYS, STRESS_UNITS, Dataset, check_monotonic,
                                    check_plausible, read_columns)
from vlab.identify.kinds import FIT_KINDS
from vlab.identify.laws import MODEL_NAMES, law_for
from vlab.identify.states import Constitutive
from vlab.scene.file import parse_toml, read_text_file

__all__ = ["FitSpec", "load_fit", "parse_fit", "parse_fit_text", "parse_model_name", "read_fit_text"]

K_MAX = 1e9  # MPa: 2000 times diamond's bulk modulus; beyond it the residuals overflow (1e300 was inf)
WEIGHT_MAX = 1e6  # a data set's weight relative to the others; 1e300 overflowed the residuals (SVD failed)
BUILTIN_KINDS = ("uniaxial", "equibiaxial", "planar", "biaxial", "simple-shear", "volumetric", "specimen", "field")
FE_DATA = ("specimen", "field")  # the kinds fitted with FE in the loop ([fe] scene)


def kinds() -> tuple[str, ...]:
    """The [[data]] kinds: the built-in ones and every kind in the registry now (one a script
    registered after this module was imported included)."""
    return BUILTIN_KINDS + tuple(FIT_KINDS)


@dataclass(frozen=True, eq=False)
class FitSpec:
    name: str
    model: Constitutive
    datasets: tuple[Dataset, ...]
    residual: str = "relative"
    starts: int = 20
    seed: int = 0
    confidence: float = 0.95
    max_evaluations: int = 400
    fe: dict | None = None
    source: dict = field(default_factory=dict)
    base_dir: Path = Path(".")
    effects: dict = field(default_factory=dict)  # vlab.identify.records: {"viscoelastic": PronySpec | None}


def parse_model_name(text: str, field_name: str = "model.name") -> tuple[str, int]:
    """"ogden-3" → ("ogden", 3); other names → (name, 1)."""
    if isinstance(text, str) and text.startswith("ogden-") and text[6:].isdigit():
        return "ogden", fields.integer(field_name + " (terms)", int(text[6:]), 1, 6)
    return fields.choice(field_name, text, MODEL_NAMES + tuple(f"ogden-{n}" for n in (1, 2, 3))), 1


def _model(raw) -> Constitutive:
    t = Table("model", raw, ("name", "terms", "incompressible", "K", "fit_K", "volumetric", "K_over_mu"))
    name, terms = parse_model_name(t.get("name"))
    if "terms" in t.raw:
        if name != "ogden":
            raise SceneError(f"model.terms is only for ogden (a series model), not {name!r}")
        terms = t.integer("terms", 1, 6)
    inc = t.get("incompressible", True)
    fit_k = t.get("fit_K", False)
    for key, v in (("incompressible", inc), ("fit_K", fit_k)):
        if not isinstance(v, bool):
            raise SceneError(f"model.{key} must be true or false, got {fields.show(v)}")
    K = t.number("K", None, gt=0, le=K_MAX, note=" (MPa, bulk modulus held fixed; for an incompressible fit "
                 "leave it out)")
    vol = t.choice("volumetric", ("quadratic", "log", "simo-taylor"), "quadratic")
    explicit_inc = "incompressible" in t.raw
    if (K is not None or fit_k) and explicit_inc and inc:
        raise SceneError("model.incompressible = true cannot be combined with model.K or model.fit_K")
    if K is not None and fit_k:
        raise SceneError("give model.K (fixed) or model.fit_K = true, not both")
    if explicit_inc and not inc and K is None and not fit_k:
        raise SceneError("model.incompressible = false needs model.K (MPa, fixed) or model.fit_K = true")
    bulk = "fit" if fit_k else "fixed" if K is not None else "incompressible"
    if "K_over_mu" in t.raw and bulk != "incompressible":
        raise SceneError("model.K_over_mu is the card's stand-in K of an incompressible fit; with model.K or "
                         "model.fit_K the card carries that K")
    ratio = t.number("K_over_mu", INCOMPRESSIBLE_K_RATIO, ge=10.0, le=1e8,
                     note=" (the card's K / mu0 of an incompressible fit)")
    return Constitutive(law_for(name, terms), bulk, K, vol, ratio)


def _columns(t: Table, kind: str) -> dict[str, str]:
    required, optional = FIT_KINDS[kind].columns if kind in FIT_KINDS else COLUMN_KEYS[kind]
    raw = t.get("columns", {})
    alt = {"stretch": "strain", "stretch2": "strain2"}
    allowed = required + optional + tuple(alt[k] for k in required if k in alt)
    ct = Table(t.field("columns"), raw, allowed)
    out = {}
    for key in required:
        if key in alt and alt[key] in ct.raw:
            if key in ct.raw:
                raise SceneError(f"{ct.field(key)}: give {key} or {alt[key]}, not both")
            out[alt[key]] = ct.raw[alt[key]]
        else:
            out[key] = ct.raw.get(key, key)
    out |= {k: ct.raw[k] for k in optional if k in ct.raw}
    for k, v in out.items():
        if not isinstance(v, str) or not v:
            raise SceneError(f"{ct.field(k)} must be a column name (string), got {fields.show(v)}")
    return out


def _dataset(raw, i: int, base: Path, scene=None) -> Dataset:
    """One [[data]] table; its ``specimen`` (any kind) is read here and carried by the Dataset;
    ``scene`` the [fe] scene, whose test kind says a specimen data set's columns."""
    from vlab.identify.specimens import split_specimen

    rest, specimen = split_specimen(raw, i)
    d = _dataset_of(rest, i, base, scene)
    return d if specimen is None else dataclasses.replace(d, specimen=specimen)


def _dataset_of(raw, i: int, base: Path, scene=None) -> Dataset:
    from vlab.identify.records import dataset_hook
    record = dataset_hook(raw, i, base)  # a lab record (relaxation, dma) or a raw machine export
    if record is not None:
        return record
    if isinstance(raw, dict) and raw.get("kind") == "field":  # a DIC fields folder (vlab.identify.field_data)
        from vlab.identify.field_data import field_dataset
        return field_dataset(raw, i, base)
    t = Table(f"data[{i}]", raw, ("file", "kind", "columns", "stress_measure", "units", "role",
                                  "weight", "name", "geometry"))
    file = t.get("file")
    if not isinstance(file, str) or not file:
        raise SceneError(f"{t.field('file')} must be a CSV file name (string), got {fields.show(file)}")
    kind = t.choice("kind", kinds())
    if kind in FIT_KINDS:
        return _closed_form_dataset(t, FIT_KINDS[kind], file, base)
    if "geometry" in t.raw:
        raise SceneError(f"{t.field('geometry')}: kind = {kind!r} takes no geometry (it is for kinds "
                         f"{', '.join(k for k, v in FIT_KINDS.items() if v.geometry)}, and raw "
                         "force–displacement exports)")
    if kind == "specimen":
        from vlab.identify.fe_columns import specimen_dataset
        return specimen_dataset(t, file, base, scene, WEIGHT_MAX)
    units = STRESS_UNITS
    unit = t.choice("units", tuple(units), "MPa")
    measure = t.choice("stress_measure", ("nominal", "true"), "nominal")
    role = t.choice("role", ("fit", "validate"), "fit")
    weight = t.number("weight", 1.0, gt=0, le=WEIGHT_MAX, note=" (relative to the other data sets)")
    name = t.get("name", Path(file).stem)
    wanted = _columns(t, kind)
    path = (base / file).resolve()
    cols = read_columns(path, wanted)
    return _to_dataset(path, name, kind, role, weight, measure, units[unit], wanted, cols)


def _closed_form_dataset(t: Table, kind, file: str, base: Path) -> Dataset:
    """A data set of a kind of vlab.identify.kinds: its columns, units, measures and geometry
    from the registry entry, the checks and arrays from its ``build``."""
    from vlab.identify.kinds.base import parse_geometry

    unit = t.choice("units", tuple(kind.units), kind.default_unit)
    if kind.measures:
        measure = t.choice("stress_measure", kind.measures, kind.measures[0])
    elif "stress_measure" in t.raw:
        raise SceneError(f"{t.field('stress_measure')} does not apply to kind = {kind.name!r} (its columns "
                         f"{', '.join(sum(kind.columns, ()))} are not stresses of one measure)")
    else:
        measure = "nominal"
    role = t.choice("role", ("fit", "validate"), "fit")
    weight = t.number("weight", 1.0, gt=0)
    name = t.get("name", Path(file).stem)
    geometry = parse_geometry(t, kind)
    wanted = _columns(t, kind.name)
    path = (base / file).resolve()
    cols = read_columns(path, wanted)
    lines = cols.pop("_line")
    if "strain" in cols:
        cols["stretch"], wanted["stretch"] = 1.0 + cols.pop("strain"), wanted.pop("strain")
    if "stretch" in cols and np.any(cols["stretch"] <= 0):
        j = int(np.argmax(cols["stretch"] <= 0))
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted['stretch']!r}: stretch must be > 0 "
                         f"(strain > -1), got {cols['stretch'][j]:g}")
    a, b, y, extra = kind.build(path, cols, wanted, lines, kind.units[unit], geometry)
    return Dataset(str(name), str(path), kind.name, role, weight, measure, a, b, y, extra)


def _to_dataset(path, name, kind, role, weight, measure, factor, wanted, cols) -> Dataset:
    lines = cols.pop("_line")
    for key in ("strain", "strain2"):
        if key in cols:
            cols[key.replace("strain", "stretch")] = 1.0 + cols.pop(key)
            wanted[key.replace("strain", "stretch")] = wanted.pop(key)
    for key in ("stretch", "stretch2"):
        if key in cols and np.any(cols[key] <= 0):
            j = int(np.argmax(cols[key] <= 0))
            raise SceneError(f"{path.name} row {int(lines[j])} column {wanted[key]!r}: stretch must be > 0 "
                             f"(strain > -1), got {cols[key][j]:g}")
    if kind == "volumetric" and np.any(cols["volume_ratio"] <= 0):
        j = int(np.argmax(cols["volume_ratio"] <= 0))
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted['volume_ratio']!r}: volume ratio must "
                         f"be > 0, got {cols['volume_ratio'][j]:g}")
    control = {"simple-shear": "shear", "volumetric": "volume_ratio"}.get(kind, "stretch")
    if kind != "biaxial":
        check_monotonic(path, wanted[control], cols[control], lines)
    if kind == "biaxial":
        a, b, y = cols["stretch"], cols["stretch2"], np.r_[cols["stress"], cols["stress2"]] * factor
    else:
        a, b, y = cols[control], None, cols["stress"] * factor
    check_plausible(path, kind, wanted.get(control, control), a if b is None else np.r_[a, a], y,
                    lines if b is None else np.r_[lines, lines])
    return Dataset(str(name), str(path), kind, role, weight, measure, a, b, y)


def _options(raw) -> dict:
    t = Table("options", raw, ("residual", "starts", "seed", "confidence", "max_evaluations"))
    return {"residual": t.choice("residual", ("relative", "absolute"), "relative"),
            "max_evaluations": t.integer("max_evaluations", 1, 100000, 400),
            "starts": t.integer("starts", 1, 1000, 20), "seed": t.integer("seed", 0, 2**31 - 1, 0),
            "confidence": t.number("confidence", 0.95, ge=0.5, le=0.999)}


def _fe_scene(data: dict, raw_data: list, base: Path):
    """The [fe] scene when a data set is of kind "specimen" (its test kind says the data's columns)."""
    if not any(isinstance(d, dict) and d.get("kind") == "specimen" for d in raw_data):
        return None
    from vlab.identify.fe_spec import specimen_scene
    return specimen_scene(data.get("fe"), base)[1][2]


def parse_fit(data: dict, base_dir: Path, default_name: str = "fit") -> FitSpec:
    """A validated FitSpec from a parsed fit file; data files are read and checked here."""
    allowed = ("name", "description", "model", "data", "options", "fe")
    for key in data:
        if key not in allowed:
            raise SceneError(f"unknown top-level key {key!r} in the fit file (allowed: {', '.join(allowed)})"
                             f"{fields.suggest(key, allowed)}")
    for key in ("model", "data"):
        if key not in data:
            raise SceneError(f"missing required [{key}]" + (" table" if key == "model" else " (one [[data]] per file)"))
    name = data.get("name", default_name)
    if not isinstance(name, str) or not name or "/" in name:
        raise SceneError(f"name must be a non-empty string without '/', got {fields.show(name)}")
    from vlab.identify.records import check_records, split_model
    model_raw, effects = split_model(data["model"])
    model = _model(model_raw)
    raw_data = data["data"]
    if not isinstance(raw_data, list) or not raw_data:
        raise SceneError("[[data]] must list at least one data set (file, kind, columns, ...)")
    scene = _fe_scene(data, raw_data, Path(base_dir))
    datasets = tuple(_dataset(d, i, Path(base_dir), scene) for i, d in enumerate(raw_data))
    needs_k = [d.kind for d in datasets
               if d.kind == "volumetric" or (d.kind in FIT_KINDS and FIT_KINDS[d.kind].compressible)]
    if model.bulk == "incompressible" and needs_k:
        raise SceneError(f"a data set of kind = \"{needs_k[0]}\" needs a compressible model (it fixes K): "
                         "model.fit_K = true or model.K")
    if not any(d.role == "fit" for d in datasets):
        raise SceneError("no data set has role = \"fit\": at least one must be fitted")
    fe = None
    if any(d.kind in FE_DATA for d in datasets):
        from vlab.identify.fe_spec import parse_fe
        fe = parse_fe(data.get("fe"), Path(base_dir), model, datasets)
    elif "fe" in data:
        raise SceneError("[fe] is only used with a data set of kind = \"specimen\" or \"field\"")
    check_records(model, effects, datasets, fe)
    from vlab.identify.specimens import check_specimens
    check_specimens(model, effects, datasets, fe)
    opts = _options(data.get("options", {}))
    return FitSpec(name, model, datasets, fe=fe, source=data, base_dir=Path(base_dir), effects=effects, **opts)


def load_fit(path: str | Path) -> FitSpec:
    """Read and validate a fit file (SceneError on any problem, naming the key or file/row/column)."""
    return parse_fit_text(path, read_fit_text(path))


def read_fit_text(path: str | Path) -> str:
    """The fit file's text, read as a scene is (bounded, UTF-8; vlab.scene.file)."""
    return read_text_file(Path(path), "fit file")


def parse_fit_text(path: str | Path, text: str) -> FitSpec:
    """The validated FitSpec of a fit file's text (read from ``path``, which resolves its data)."""
    path = Path(path)
    return parse_fit(parse_toml(text, str(path), "fit file"), path.parent, path.stem)
