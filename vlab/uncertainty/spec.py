"""The scene's ``[uncertainty]`` table (validated like every key: a SceneError naming the field).

    [uncertainty]
    samples = 200                  # Monte Carlo samples (1..100000; --samples overrides)
    seed = 0                       # sample i draws from numpy's default_rng([seed, i])
    distribution = "normal"        # of the dimension tolerances: "normal" (tolerance = U, k = 2)
                                   # or "rectangular" (tolerance = half-width)
    width = 0.5                    # mm, tolerance of the gauge-section width   } default: the
    thickness = 0.2                # mm, tolerance of the thickness             } standard's table
    gauge_length = 0.5             # mm, error of the extensometer's gauge-length setting (default 0:
                                   # the class's own q_Le is drawn anyway)
    micrometer = 0.01              # mm: the lab measures width and thickness at this resolution
                                   # (absent: the analysis uses the nominal dimensions)
    load_cell_class = 1            # ISO 7500-1: 0.5, 1, 2, 3 or "none" (default 1, ISO 527-1)
    extensometer_class = 1         # ISO 9513: 0.2, 0.5, 1, 2 or "none" (default 1, ISO 527-1)
    resolution = true              # quantise the readings at the classes' resolution
    window_shift = 0.0001          # strain: half-width of a rectangular shift of the modulus window
    material = { E = 0.02 }        # relative standard uncertainty of card constants (normal)
    alignment = { offset = 0.05, tilt = 0.1 }  # standard uncertainties (normal) of the moving grip's
                                   # offset (mm) and tilt (degrees), test.grips = "clamped"
                                   # (vlab.loading.misalignment; results.json → bending); a number
                                   # is the thickness plane's (offset along z, tilt about y), a
                                   # list of two both planes': offset = [u_ey, u_ez], tilt = [u_θy, u_θz]
    grip_slip = 2e-4               # mm/N: the grips' slip compliance C is somewhere in [0, grip_slip]
                                   # (rectangular; test.grip_slip: the crosshead reads travel + C F)

Shapes: block (width = size[1], thickness = size[2], the extensometer over measure.gauge_length or
L/2) and dogbone (its dimensions), in a uniaxial test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from vlab import fields
from vlab.fields import SceneError, Table
from vlab.scene.test import misalignment_pair
from vlab.uncertainty.classes import EXTENSOMETER, LOAD_CELL, standard_tolerances

__all__ = ["Source", "UncertaintySpec", "parse_uncertainty", "KEYS", "FE_KINDS"]

KEYS = ("samples", "seed", "distribution", "width", "thickness", "gauge_length", "micrometer",
        "load_cell_class", "extensometer_class", "resolution", "window_shift", "material", "alignment",
        "grip_slip")


#: the sources that change the FE run (the others act on the lab's analysis only)
FE_KINDS = ("width", "thickness", "gauge", "gauge_rel", "material", "window", "offset_y", "offset_z", "tilt_y",
            "tilt_z", "slip")


@dataclass(frozen=True)
class Source:
    """One input quantity: its deviation from nominal is drawn per sample.

    ``kind``: where it acts — "width", "thickness", "gauge" (the extensometer's gauge length, mm),
    "gauge_rel" (relative), "material" (relative, of ``key``), "window" (strain), "load_cell",
    "extensometer", "transverse" (relative errors of the readings), "micrometer_width",
    "micrometer_thickness" (mm, the lab's measurement), "offset_y", "offset_z" (mm), "tilt_y",
    "tilt_z" (degrees) of the moving grip (test.misalignment), "slip" (mm/N, test.grip_slip).
    ``fe``: whether it changes the FE run. ``centre``: the value the deviation is drawn about (the
    slip's midpoint; 0 for the others, whose nominal is the scene's).
    """

    name: str
    kind: str
    distribution: str  # "normal" | "rectangular"
    half_width: float  # rectangular: the half-width; normal: the expanded U (k = 2)
    unit: str
    source: str
    key: str = ""
    centre: float = 0.0

    @property
    def u(self) -> float:
        """Standard uncertainty: U/2 (normal, k = 2) or a/√3 (rectangular, GUM 4.3.7)."""
        return self.half_width / 2.0 if self.distribution == "normal" else self.half_width / math.sqrt(3.0)

    @property
    def fe(self) -> bool:
        return self.kind in FE_KINDS

    def draw(self, rng) -> float:
        if self.distribution == "normal":
            return float(rng.normal(0.0, self.u))
        return float(rng.uniform(-self.half_width, self.half_width))


@dataclass(frozen=True)
class UncertaintySpec:
    samples: int
    seed: int
    sources: tuple[Source, ...]
    nominal: dict  # width, thickness, gauge_length (mm) of the analysis
    load_cell: dict | None
    extensometer: dict | None
    resolution: bool
    micrometer: float | None


def _class(t: Table, key: str, table: dict, standard: str):
    raw = t.get(key, 1)
    if raw == "none":
        return None, None
    allowed = ", ".join(f"{c:g}" for c in table)
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or float(raw) not in table:
        raise SceneError(f"{t.field(key)} must be a {standard} class ({allowed}) or \"none\", got {fields.show(raw)}")
    return float(raw), table[float(raw)]


def _nominal(scene) -> tuple[dict, str]:
    sp = scene.specimen
    if scene.test.kind != "uniaxial":
        raise SceneError(f"[uncertainty] budgets a uniaxial test (E and nu); test.kind is {scene.test.kind!r}")
    if sp.shape == "block":
        L, W, T = sp.size
        gauge = scene.measure.gauge_length or L / 2
        return {"width": float(W), "thickness": float(T), "gauge_length": float(gauge)}, ""
    if sp.shape == "dogbone":
        d = sp.dimensions
        return {"width": d.width, "thickness": d.thickness,
                "gauge_length": scene.measure.gauge_length or d.gauge_length}, d.standard
    raise SceneError(f"[uncertainty] perturbs a block or a dogbone; specimen.shape is {sp.shape!r}")


def _dimension(t: Table, key: str, nominal: float, default: float | None, dist: str, std: str) -> Source | None:
    tol = t.number(key, default if default is not None else 0.0, ge=0, note=" (mm, a tolerance)")
    if tol >= nominal:
        raise SceneError(f"{t.field(key)} = {tol:g} mm is not smaller than the dimension itself ({nominal:g} mm)")
    if tol == 0:
        return None
    where = "scene" if key in t.raw else f"{std} table (vlab.uncertainty.classes)"
    what = "extensometer gauge length setting" if key == "gauge_length" else f"specimen {key}"
    return Source(f"{what}", "gauge" if key == "gauge_length" else key, dist, tol, "mm", where)


def _material(t: Table, scene) -> list[Source]:
    raw = t.get("material", {})
    mt = Table(t.field("material"), raw, tuple(k for k, v in scene.source["material"].items()
                                              if isinstance(v, (int, float)) and not isinstance(v, bool)))
    out = []
    for key in mt.raw:
        u = mt.number(key, gt=0, lt=0.5, note=" (relative standard uncertainty)")
        out.append(Source(f"material {key}", "material", "normal", 2.0 * u, "relative", "scene", key))
    return out


def _micrometer(t: Table, nominal: dict) -> tuple[float | None, list[Source]]:
    """(the micrometer's resolution, the rectangular sources of reading width and thickness with
    it: half-width resolution / 2), none without a micrometer."""
    micrometer = t.number("micrometer", None, gt=0, note=" (mm, resolution)")
    out = []
    if micrometer is not None:
        for k in ("width", "thickness"):
            if micrometer >= nominal[k]:
                raise SceneError(f"{t.field('micrometer')} = {micrometer:g} mm is not smaller than the {k} "
                                 f"({nominal[k]:g} mm)")
            out.append(Source(f"micrometer reading of the {k}", f"micrometer_{k}", "rectangular", micrometer / 2,
                              "mm", "resolution / 2 (GUM F.2.2.1)"))
    return micrometer, out


def _window(t: Table, scene) -> list[Source]:
    """The rectangular shift of the modulus window (strain), below the window's start; none at 0."""
    shift = t.number("window_shift", 0.0, ge=0, note=" (strain)")
    lo = scene.measure.modulus_window[0]
    if shift >= lo and shift > 0:
        raise SceneError(f"{t.field('window_shift')} = {shift:g} must be below the window's start "
                         f"measure.modulus_window[0] = {lo:g} (the shifted window must stay at strain >= 0)")
    return [Source("modulus window position", "window", "rectangular", shift, "strain", "scene")] if shift > 0 else []


ALIGNMENT_LIMITS = {"offset": (" (mm, standard uncertainty)", None), "tilt": (" (degrees, standard uncertainty)", 10.0)}
#: the sources' kinds and labels, in test.misalignment's order of each pair ([e_y, e_z], [θ_y, θ_z])
ALIGNMENT_SOURCES = {"offset": (("offset_y", "width y"), ("offset_z", "thickness z")),
                     "tilt": (("tilt_y", "about y, thickness plane"), ("tilt_z", "about z, width plane"))}


def _alignment_pair(at: Table, key: str, note: str, le) -> list[tuple[str, str, float]]:
    """(kind, label, u) of ``alignment.key``: a list of two in test.misalignment's order, or a
    number, the thickness plane's (vlab.scene.test.misalignment_pair)."""
    raw = at.raw.get(key, 0.0)
    if isinstance(raw, list):
        what = "[u_ey, u_ez]" if key == "offset" else "[u_theta_y, u_theta_z]"
        pair = fields.vector(at.field(key), raw, 2, what, ge=0, le=le, note=note)
    else:
        pair = misalignment_pair(key, at.number(key, 0.0, ge=0, le=le, note=note))
    return [(kind, label, u) for (kind, label), u in zip(ALIGNMENT_SOURCES[key], pair)]


def _alignment(t: Table, scene) -> list[Source]:
    """``alignment = {offset = u_e, tilt = u_θ}``: normal draws of the moving grip's offset (mm) and
    tilt (degrees) about test.misalignment (0 if absent), in the thickness plane (a number) or in
    both (a list of two); u_θ <= 10° keeps the draws below 90°."""
    if "alignment" not in t.raw:
        return []
    at = Table(t.field("alignment"), t.raw["alignment"], tuple(ALIGNMENT_LIMITS))
    if scene.test.grips != "clamped":
        raise SceneError(f"{t.field('alignment')} misaligns a clamped grip: it needs test.grips = 'clamped' "
                         f"(a roller grip prescribes no lateral motion), got {scene.test.grips!r}")
    out = []
    for key, (note, le) in ALIGNMENT_LIMITS.items():
        for kind, label, u in _alignment_pair(at, key, note, le):
            if u > 0:
                unit = "mm" if key == "offset" else "degrees"
                out.append(Source(f"grip {key} ({label})", kind, "normal", 2.0 * u, unit, "scene"))
    return out


def _slip(t: Table, scene) -> list[Source]:
    """``grip_slip = C_max``: the grips' slip compliance C (mm/N) rectangular on [0, C_max] (a lab
    bounds the slip it cannot see: C = C_max/2 ± C_max/2, u = C_max/(2√3)); the run's
    test.grip_slip is C (vlab.measure.recorder.Curve.crosshead_strain). None at 0."""
    c_max = t.number("grip_slip", 0.0, ge=0, le=10.0, note=" (mm/N, the largest slip compliance of the grips)")
    if c_max == 0:
        return []
    if scene.test.grip_slip:
        raise SceneError(f"{t.field('grip_slip')} draws the slip compliance on [0, {c_max:g}] mm/N; the scene "
                         f"also fixes it (test.grip_slip = {scene.test.grip_slip:g}): give one of the two")
    return [Source("grip slip", "slip", "rectangular", c_max / 2.0, "mm/N", "scene: rectangular on [0, C_max]",
                   centre=c_max / 2.0)]


def parse_uncertainty(raw, scene) -> UncertaintySpec:
    """The validated [uncertainty] table of a parsed scene (raw: the table's dict)."""
    t = Table("uncertainty", raw, KEYS)
    nominal, standard = _nominal(scene)
    samples = t.integer("samples", 1, 100000, 200)
    seed = t.integer("seed", 0, 2 ** 31 - 1, 0)
    dist = t.choice("distribution", ("normal", "rectangular"), "normal")
    tol = standard_tolerances(standard) if standard else {}
    src = [s for s in (_dimension(t, k, nominal[k], tol.get(k) if k != "gauge_length" else None, dist, standard)
                       for k in ("width", "thickness", "gauge_length")) if s is not None]
    micrometer, readings = _micrometer(t, nominal)
    src += readings
    lc_class, lc = _class(t, "load_cell_class", LOAD_CELL, "ISO 7500-1")
    ex_class, ex = _class(t, "extensometer_class", EXTENSOMETER, "ISO 9513")
    if lc is not None:
        src.append(Source("load cell", "load_cell", "rectangular", lc["q"], "relative", f"ISO 7500-1 class {lc_class:g}"))
    if ex is not None:
        cite = f"ISO 9513 class {ex_class:g}"
        src += [Source("extensometer (axial)", "extensometer", "rectangular", ex["bias_rel"], "relative", cite),
                Source("extensometer (transverse)", "transverse", "rectangular", ex["bias_rel"], "relative", cite),
                Source("extensometer gauge length (class)", "gauge_rel", "rectangular", ex["q_Le"], "relative", cite)]
    resolution = t.get("resolution", True)
    if not isinstance(resolution, bool):
        raise SceneError(f"{t.field('resolution')} must be true or false, got {fields.show(resolution)}")
    src += _window(t, scene) + _material(t, scene) + _alignment(t, scene) + _slip(t, scene)
    return UncertaintySpec(samples, seed, tuple(src), nominal,
                           None if lc is None else lc | {"class": lc_class},
                           None if ex is None else ex | {"class": ex_class}, resolution, micrometer)
