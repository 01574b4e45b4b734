"""A DIC fields folder as a `vlab fit` data set (kind = "field"), read and checked.

    [[data]]
    kind = "field"
    fields = "dic"                 # folder: fields/<stem>.csv, levels.csv, maybe dic.json
    strain_noise = 1e-4            # σ_E (strain); default dic.json's noise floor (the larger of σ_Exx,
                                   #   σ_Eyy of vlab run's static pair), else 1e-4
    force_resolution = 0.01        # σ_F (N); default 1e-3 × the largest |force| in levels.csv
    strain_window = 5              # only without dic.json's settings: the DIC's strain window (grid points)
    subset = 31                    # only without dic.json's settings: the subset size (px; default 0)
    [data.camera]                  # overrides dic.json's "camera" (real images from `vlab dic` have none)
    pixels = [1024, 1024]          # W, H
    mm_per_px = 0.05               # p, mm on the specimen per pixel
    centre = [0.0, 0.0]            # c (mm): the face point at the image centre
    face = { axis = 2, side = 1 }  # as vlab.dic.face.face_of takes them (axis also "x", "y", "z")

``levels.csv`` has the columns image, displacement, force: the image stem (its field is
fields/<stem>.csv), the grip displacement Δ = (λ_grip − 1) L_grip in mm (the crosshead travel) and
the load-cell force in N. A row with Δ = 0 and no field file is the reference image. Each field CSV
is `vlab dic`'s (vlab.dic.output: x_px, y_px, u_px, v_px, exx, eyy, exy, ...; empty where the
subset failed) on one subset grid shared by every level: x right, y down, step s px. The subset
centre (x, y) in px is the face point (mm) X₁ = c₁ + (x − (W − 1)/2) p, X₂ = c₂ − (y − (H − 1)/2) p
(vlab.dic.camera's pixel centres). Every error is a SceneError naming the file, row and column.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table

__all__ = ["FieldLevel", "FieldData", "field_dataset", "LEVEL_COLUMNS", "FIELD_COLUMNS"]

LEVEL_COLUMNS = ("image", "displacement", "force")
FIELD_COLUMNS = ("x_px", "y_px", "u_px", "v_px", "exx", "eyy", "exy")
STRAIN_NOISE = 1e-4      # default σ_E: 100 µε, above vlab dic's strain noise at 1 % grey noise (docs/dic.md)
FORCE_SHARE = 1e-3       # default σ_F = 1e-3 × max |F| (a class-0.5 load cell resolves better than that)
KEYS = ("kind", "fields", "name", "role", "weight", "strain_noise", "force_resolution", "strain_window", "subset",
        "camera")


@dataclass(frozen=True, eq=False)
class FieldLevel:
    """One deformed image: its stem and file, grip displacement (mm), force (N) and the DIC
    strains (rows = y, columns = x of the grid; NaN where empty); ``valid`` where u and v are."""

    image: str
    file: str
    displacement: float
    force: float
    exx: np.ndarray
    eyy: np.ndarray
    exy: np.ndarray
    valid: np.ndarray
    rows: np.ndarray  # CSV line of each grid point
    xs: np.ndarray    # the grid's x_px (columns) and y_px (rows)
    ys: np.ndarray


@dataclass(frozen=True, eq=False)
class FieldData:
    """The folder: grid axes xs, ys (px), step (px), strain window (grid points), camera
    (pixels, mm_per_px, centre, face), the levels, σ_E and σ_F, the subset size (px; 0 unknown)."""

    folder: str
    xs: np.ndarray
    ys: np.ndarray
    step: float
    window: int
    camera: dict
    levels: tuple[FieldLevel, ...]
    strain_noise: float
    force_resolution: float
    subset: int = 0
    source: dict | None = None  # dic.json's "source" (vlab run: what made the images); None for real images


def field_dataset(raw: dict, i: int, base: Path):
    """The Dataset of one [[data]] table of kind "field": a = grip displacements, y = forces,
    extra["field"] = FieldData."""
    from vlab.identify.datasets import Dataset

    t = Table(f"data[{i}]", raw, KEYS)
    name = t.get("fields")
    if not isinstance(name, str) or not name:
        raise SceneError(f"{t.field('fields')} must be a DIC fields folder (string), got {fields.show(name)}")
    folder = (base / name).resolve()
    if not folder.is_dir():
        raise SceneError(f"{t.field('fields')}: {folder} is not a folder (it must hold fields/ and levels.csv)")
    t.choice("role", ("fit",), "fit")  # a field is fitted; held-out fields are not implemented
    settings = _dic_json(folder)
    camera = _camera(t, settings.get("camera"), folder)
    levels = _levels(folder)
    xs, ys, step = _grid(levels)
    window = _setting(t, settings, folder, "strain_window", 3, 101, odd=True)
    subset = _setting(t, settings, folder, "subset", 0, 1001, default=0)
    fmax = max(abs(lv.force) for lv in levels)
    sigma_f = t.number("force_resolution", max(FORCE_SHARE * fmax, 1e-12), gt=0, note=" (N)")
    sigma_e = t.number("strain_noise", _noise_floor(settings), gt=0, le=1.0, note=" (strain)")
    data = FieldData(str(folder), xs, ys, step, window, camera, levels, sigma_e, sigma_f, subset,
                     _source(settings, folder))
    disp = np.array([lv.displacement for lv in levels])
    force = np.array([lv.force for lv in levels])
    return Dataset(str(t.get("name", folder.name)), str(folder), "field", "fit",
                   t.number("weight", 1.0, gt=0, le=1e6), "nominal", disp, None, force, {"field": data})


def _dic_json(folder: Path) -> dict:
    path = folder / "dic.json"
    if not path.exists():
        return {}
    try:
        d = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise SceneError(f"{path}: not a readable JSON file ({exc})") from None
    if not isinstance(d, dict):
        raise SceneError(f"{path}: must hold a JSON object (vlab dic's dic.json)")
    return d


def _source(settings: dict, folder: Path) -> dict | None:
    """dic.json's "source" (vlab run's record of the scene and material that made the images), None
    if absent; a SceneError naming the file when it is there without a material table."""
    source = settings.get("source")
    if source is None:
        return None
    if not isinstance(source, dict) or not isinstance(source.get("material"), dict):
        raise SceneError(f"{folder / 'dic.json'} source: must be an object with a \"material\" table (vlab run "
                         f"writes the scene's [material] there), got {fields.show(source)}")
    return source


def _noise_floor(settings: dict) -> float:
    """The default σ_E: the larger of the static pair's σ_Exx, σ_Eyy (dic.json's noise_floor, µε,
    written by vlab run) when there is one above zero, else STRAIN_NOISE."""
    floor = settings.get("noise_floor")
    if not isinstance(floor, dict):
        return STRAIN_NOISE
    sig = [floor.get(k) for k in ("sigma_exx_microstrain", "sigma_eyy_microstrain")]
    sig = [float(v) for v in sig if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)]
    return max(sig) * 1e-6 if sig and max(sig) > 0 else STRAIN_NOISE


def _camera(t: Table, from_json, folder: Path) -> dict:
    """pixels, mm_per_px, centre, face: [data.camera] over dic.json's "camera" (there the centre is
    "centre_mm", as vlab run writes it; "centre" is read too)."""
    raw = dict(from_json) if isinstance(from_json, dict) else {}
    if "centre_mm" in raw:
        raw["centre"] = raw.pop("centre_mm")
    where = {k: f"{folder / 'dic.json'} camera.{k}" for k in raw}
    own = Table(t.field("camera"), t.get("camera", {}), ("pixels", "mm_per_px", "centre", "face"))
    raw |= own.raw
    where |= {k: own.field(k) for k in own.raw}
    for k in ("pixels", "mm_per_px", "centre", "face"):
        if k not in raw:
            raise SceneError(f"{own.field(k)} is missing: the camera's {k} comes from dic.json's \"camera\" "
                             f"(vlab run writes it) or from [data.camera] (images from vlab dic)")
    pix = raw["pixels"]
    if not (isinstance(pix, list) and len(pix) == 2 and all(isinstance(n, int) and 16 <= n <= 16384 for n in pix)):
        raise SceneError(f"{where['pixels']} must be [W, H], integers in [16, 16384], got {fields.show(pix)}")
    face = raw["face"]
    if not isinstance(face, dict) or "axis" not in face or "side" not in face:
        raise SceneError(f"{where['face']} must be a table {{ axis = 0..2 (or \"x\", \"y\", \"z\"), side = ±1 }}, "
                         f"got {fields.show(face)}")
    return {"pixels": (int(pix[0]), int(pix[1])),
            "mm_per_px": fields.number(where["mm_per_px"], raw["mm_per_px"], gt=0, note=" (mm per pixel)"),
            "centre": fields.vector(where["centre"], raw["centre"], 2, "(mm, the face point at the image centre)"),
            "face": (_axis(where["face"], face["axis"]), _side(where["face"], face["side"]))}


def _axis(where: str, v) -> int:
    """A face's axis: 0, 1, 2 or its name x, y, z (vlab run's dic.json writes the name)."""
    if isinstance(v, str) and v in ("x", "y", "z"):
        return "xyz".index(v)
    return fields.integer(f"{where}.axis", v, 0, 2)


def _side(where: str, v) -> int:
    if v not in (-1, 1) or isinstance(v, bool):
        raise SceneError(f"{where}.side must be 1 or -1 (the side of the specimen the camera is on), "
                         f"got {fields.show(v)}")
    return int(v)


def _setting(t: Table, settings: dict, folder: Path, key: str, lo: int, hi: int, default=fields.REQUIRED,
             odd: bool = False) -> int:
    """A DIC setting: the fit file's data.<key> over dic.json's settings.<key> (default if neither)."""
    s = settings.get("settings") if isinstance(settings.get("settings"), dict) else {}
    if key in t.raw or key not in s:
        where, v = t.field(key), t.integer(key, lo, hi, default)
    else:
        where = f"{folder / 'dic.json'} settings.{key}"
        v = fields.integer(where, s[key], lo, hi)
    if odd and v % 2 == 0:
        raise SceneError(f"{where} must be odd (grid points), got {v}")
    return v


def _rows(path: Path, wanted: tuple[str, ...]):
    """(header index of each wanted column, [(line, cells)]) of a CSV; SceneError naming the file."""
    from vlab.scene.file import read_text_file

    if not path.is_file():
        raise SceneError(f"{path}: no such file")
    text = read_text_file(path, "data file")
    lines = list(csv.reader(text.splitlines()))
    if not lines:
        raise SceneError(f"{path}: empty file (a header row {','.join(wanted)} is needed)")
    header = [h.strip() for h in lines[0]]
    for c in wanted:
        if c not in header:
            raise SceneError(f"{path.name}: missing column {c!r} (needed: {', '.join(wanted)})"
                             f"{fields.suggest(c, header)}")
    index = {c: header.index(c) for c in wanted}
    body = [(n + 1, row) for n, row in enumerate(lines) if n > 0 and any(x.strip() for x in row)]
    if not body:
        raise SceneError(f"{path}: no data rows under the header")
    return index, body


def _number(path: Path, line: int, column: str, text: str, empty_ok: bool) -> float:
    text = text.strip()
    if text == "" and empty_ok:
        return math.nan
    try:
        v = float(text)
    except ValueError:
        raise SceneError(f"{path.name} row {line} column {column!r}: {text!r} is not a number") from None
    if not math.isfinite(v) and not empty_ok:
        raise SceneError(f"{path.name} row {line} column {column!r}: {text!r} is not a finite number")
    return v


def _cells(path: Path, index: dict, line: int, row: list, columns, empty_ok=()) -> dict:
    if len(row) <= max(index[c] for c in columns):
        raise SceneError(f"{path.name} row {line}: {len(row)} cells, fewer than the header's columns")
    return {c: _number(path, line, c, row[index[c]], c in empty_ok) for c in columns}


def _levels(folder: Path) -> tuple[FieldLevel, ...]:
    """levels.csv's rows with their fields (the reference row, Δ = 0 without a field, skipped)."""
    path = folder / "levels.csv"
    index, body = _rows(path, LEVEL_COLUMNS)
    out, seen = [], set()
    for line, row in body:
        image = row[index["image"]].strip() if len(row) > index["image"] else ""
        if not image or image in seen:
            raise SceneError(f"{path.name} row {line} column 'image': "
                             + ("empty" if not image else f"{image!r} listed twice"))
        seen.add(image)
        v = _cells(path, index, line, row, ("displacement", "force"))
        field = folder / "fields" / f"{image}.csv"
        if not field.is_file():
            if v["displacement"] == 0:
                continue  # the reference image: no field of its own
            raise SceneError(f"{path.name} row {line} column 'image': {image!r} has no field file "
                             f"{field.relative_to(folder)} (vlab dic writes fields/<image stem>.csv)")
        out.append(_field(field, image, v["displacement"], v["force"]))
    if not out:
        raise SceneError(f"{path}: no level with a field to fit (every row is the reference)")
    disp = [lv.displacement for lv in out]
    if any(b <= a for a, b in zip(disp, disp[1:])) or disp[0] < 0:
        raise SceneError(f"{path.name} column 'displacement': the levels must rise from 0 (a monotonic tension "
                         f"test), got {', '.join(f'{d:g}' for d in disp)}")
    return tuple(out)


def _field(path: Path, image: str, displacement: float, force: float) -> FieldLevel:
    index, body = _rows(path, FIELD_COLUMNS)
    vals = np.array([[*_cells(path, index, line, row, FIELD_COLUMNS, FIELD_COLUMNS[2:]).values(), line]
                     for line, row in body])
    x, y = vals[:, 0], vals[:, 1]
    for c, a in (("x_px", x), ("y_px", y)):
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise SceneError(f"{path.name} row {int(vals[bad[0], 7])} column {c!r}: a subset centre is needed")
    xs, ys = np.unique(x), np.unique(y)
    if xs.size * ys.size != len(vals):
        raise SceneError(f"{path.name}: the {len(vals)} subset centres are not a full grid "
                         f"({xs.size} columns x_px × {ys.size} rows y_px)")
    order = np.lexsort((x, y))
    grid = vals[order].reshape(ys.size, xs.size, 8)
    if np.any(grid[..., 0] != xs[None, :]) or np.any(grid[..., 1] != ys[:, None]):
        raise SceneError(f"{path.name}: a subset centre is listed twice (columns x_px, y_px)")
    valid = np.isfinite(grid[..., 2]) & np.isfinite(grid[..., 3])
    return FieldLevel(image, str(path), displacement, force, grid[..., 4], grid[..., 5], grid[..., 6], valid,
                      grid[..., 7].astype(int), xs, ys)


def _grid(levels) -> tuple[np.ndarray, np.ndarray, float]:
    """The shared grid (xs, ys) and its step: uniform, the same along x and y and in every level."""
    first = levels[0]
    xs, ys = first.xs, first.ys
    for lv in levels[1:]:
        if lv.xs.shape != xs.shape or lv.ys.shape != ys.shape or np.any(lv.xs != xs) or np.any(lv.ys != ys):
            raise SceneError(f"{Path(lv.file).name}: its subset grid differs from {Path(first.file).name}'s "
                             "(every level is correlated on the reference image's grid)")
    steps = np.r_[np.diff(xs), np.diff(ys)]
    if steps.size == 0 or xs.size < 3 or ys.size < 3 or np.ptp(steps) > 1e-9 * steps.max():
        raise SceneError(f"{Path(first.file).name}: the subset centres must be a uniform grid of at least 3 × 3 "
                         f"with one step along x_px and y_px, got steps {sorted(set(steps.tolist()))}")
    return xs, ys, float(steps[0])

