"""``[instruments]``: instruments beyond the load cell and the point extensometers. One so far,
``[instruments.dic]``, the virtual camera and digital image correlation (vlab.dic.camera,
vlab.dic.correlate; docs/dic.md):

    [instruments.dic]
    face = "top"                 # top (z max, seen from +z), bottom, front (y min), back (y max)
    subset = 31                  # DIC settings: subset (odd px), step (px), strain_window (odd,
    step = 10                    #   grid points), search, tolerance, max_iterations, min_zncc,
    strain_window = 5            #   interpolation, shape_function
    metrics = "full"             # full: + spatial resolution and MEI (a few more images); basic
    [instruments.dic.camera]
    pixels = [512, 256]          # W × H
    field_of_view = 40.0         # mm across W (or mm_per_px); exactly one
    bit_depth = 16               # noise (share of full scale), blur (px), supersample, seed,
                                 #   centre = [x₁, x₂] (face mm), background
    [instruments.dic.speckle]
    size = 4.0                   # px of the reference image; density in (0, 1]; seed

The ranges are those vlab.dic.camera.Camera / Speckle and vlab.dic.correlate.Settings accept
(a test holds them equal); the values are kept as plain keyword dicts, so parsing a scene imports
none of vlab.dic. Whether the camera sees the face needs the mesh: the run checks it before
solving (vlab.pipeline.dic).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vlab import fields
from vlab.fields import SceneError

__all__ = ["DicSpec", "InstrumentsSpec", "FACES", "INTERPOLATIONS", "METRICS", "parse_instruments"]

#: face name -> (mesh axis of the normal, side ±1), vlab.dic.face.face_of's arguments
FACES = {"top": (2, 1), "bottom": (2, -1), "front": (1, -1), "back": (1, 1)}
INTERPOLATIONS = ("bicubic", "biquintic")  # vlab.dic.icgn.ORDERS
SHAPE_FUNCTIONS = ("affine",)
CAMERA_KEYS = ("pixels", "field_of_view", "mm_per_px", "bit_depth", "noise", "blur", "supersample", "seed",
               "centre", "background")
SPECKLE_KEYS = ("size", "density", "seed")
SETTINGS_KEYS = ("subset", "step", "strain_window", "search", "tolerance", "max_iterations", "min_zncc",
                 "interpolation", "shape_function")
SEED_MAX = 2**31 - 1
#: the DIC Challenge metrics a run measures: "basic" the static pair's noise floor and the sub-pixel
#: translation bias; "full" also the spatial resolution and the MEI (vlab.dic.resolution)
METRICS = ("full", "basic")


@dataclass(frozen=True)
class DicSpec:
    """face: its name and (axis, side); camera, speckle, settings: keyword arguments of
    vlab.dic.camera.Camera, .Speckle and vlab.dic.correlate.Settings (only the keys given);
    metrics: one of METRICS."""

    face: str
    axis: int
    side: int
    camera: dict
    speckle: dict
    settings: dict
    metrics: str = "full"


@dataclass(frozen=True)
class InstrumentsSpec:
    dic: DicSpec | None = None


def parse_instruments(raw: Any, specimen) -> InstrumentsSpec | None:
    """The [instruments] section, or None when the scene has none (nothing extra is built)."""
    if raw is None:
        return None
    t = fields.Table("instruments", raw, ("dic",))
    if "dic" not in t.raw:
        return InstrumentsSpec()
    return InstrumentsSpec(dic=_parse_dic(t.raw["dic"], specimen))


def _parse_dic(raw: Any, specimen) -> DicSpec:
    t = fields.Table("instruments.dic", raw, ("face", "camera", "speckle", "metrics") + SETTINGS_KEYS)
    if specimen.shape == "sheet":
        raise SceneError(f"[instruments.dic] needs a 3-D specimen with a flat face to look at; "
                         f"specimen.shape = {specimen.shape!r} is meshed in 2-D")
    face = t.choice("face", tuple(FACES), default="top")
    camera = _camera(t.raw.get("camera", {}))
    settings = _settings(t)
    need = settings.get("subset", 31) + 2
    if min(camera["pixels"]) < need:
        raise SceneError(f"instruments.dic.subset = {settings.get('subset', 31)} px does not fit the camera's "
                         f"{camera['pixels'][0]} × {camera['pixels'][1]} px image: instruments.dic.camera.pixels "
                         f"must be ≥ subset + 2 = {need} each way")
    return DicSpec(face, *FACES[face], camera, _speckle(t.raw.get("speckle", {})), settings,
                   t.choice("metrics", METRICS, default="full"))


def _camera(raw: Any) -> dict:
    t = fields.Table("instruments.dic.camera", raw, CAMERA_KEYS)
    out: dict = {"pixels": _pixels(t)}
    scales = [k for k in ("field_of_view", "mm_per_px") if k in t.raw]
    if len(scales) != 1:
        raise SceneError("instruments.dic.camera: give exactly one of field_of_view (mm across the image "
                         f"width) and mm_per_px (mm), got {' and '.join(scales) or 'neither'}")
    out[scales[0]] = t.number(scales[0], gt=0, le=1e4, note=" (mm)")
    if "bit_depth" in t.raw:
        bits = t.raw["bit_depth"]
        if isinstance(bits, bool) or bits not in (8, 16):
            raise SceneError(f"{t.field('bit_depth')} must be 8 or 16, got {fields.show(bits)}")
        out["bit_depth"] = int(bits)
    for key, hi, note in (("noise", 0.5, " (grey-level std, share of full scale)"), ("blur", 50, " (Gaussian σ, px)"),
                          ("background", 1, " (grey off the specimen, share of full scale)")):
        if key in t.raw:
            out[key] = t.number(key, ge=0, le=hi, note=note)
    if "supersample" in t.raw:
        out["supersample"] = t.integer("supersample", 1, 8)
    if "seed" in t.raw:
        out["seed"] = t.integer("seed", 0, SEED_MAX)
    if "centre" in t.raw:
        out["centre"] = fields.vector(t.field("centre"), t.raw["centre"], 2, "[x₁, x₂] (mm on the face)")
    return out


def _pixels(t: fields.Table) -> tuple[int, int]:
    raw = t.get("pixels", [1024, 1024])
    if not isinstance(raw, list) or len(raw) != 2:
        raise SceneError(f"{t.field('pixels')} must be [width, height], integers 16..16384, got {fields.show(raw)}")
    return tuple(fields.integer(f"{t.field('pixels')}[{i}]", v, 16, 16384) for i, v in enumerate(raw))


def _speckle(raw: Any) -> dict:
    t = fields.Table("instruments.dic.speckle", raw, SPECKLE_KEYS)
    out: dict = {}
    if "size" in t.raw:
        out["size"] = t.number("size", ge=1, le=100, note=" (speckle diameter, px)")
    if "density" in t.raw:
        out["density"] = t.number("density", gt=0, le=1, note=" (share of the face covered)")
    if "seed" in t.raw:
        out["seed"] = t.integer("seed", 0, SEED_MAX)
    return out


def _odd(t: fields.Table, key: str, lo: int, hi: int, what: str) -> int:
    value = t.integer(key, lo, hi)
    if value % 2 == 0:
        raise SceneError(f"{t.field(key)} must be an odd integer {lo}..{hi} ({what}), got {value}")
    return value


def _settings(t: fields.Table) -> dict:
    """The DIC settings given (vlab.dic.correlate.Settings' keywords and ranges)."""
    out: dict = {}
    if "subset" in t.raw:
        out["subset"] = _odd(t, "subset", 7, 255, "px")
    if "strain_window" in t.raw:
        out["strain_window"] = _odd(t, "strain_window", 3, 51, "grid points")
    for key, hi in (("step", 1000), ("search", 1000), ("max_iterations", 1000)):
        if key in t.raw:
            out[key] = t.integer(key, 1, hi)
    if "tolerance" in t.raw:
        out["tolerance"] = t.number("tolerance", gt=0, le=0.1, note=" (px)")
    if "min_zncc" in t.raw:
        out["min_zncc"] = t.number("min_zncc", ge=-1, lt=1)
    if "interpolation" in t.raw:
        out["interpolation"] = t.choice("interpolation", INTERPOLATIONS)
    if "shape_function" in t.raw:
        out["shape_function"] = t.choice("shape_function", SHAPE_FUNCTIONS)
    return out
