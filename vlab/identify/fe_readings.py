"""What a specimen data set (``kind = "specimen"``) holds for each test kind of its [fe] scene: the
registry of readings an FE-in-the-loop fit matches.

Contract. ``SPECIMEN_KINDS[test.kind]`` is a ``SpecimenKind``: its ``channels``, each a
``Channel`` of ``controls`` (the data give one: the variable the curve runs along, strictly
monotonic) and ``readings`` (the data give one: the instrument matched), the first channel
required, the others present when the data name one of their readings. Every ``Quantity`` says
- ``key``: its data column key (``columns = { key = "<CSV header>" }``; default: the key itself),
  ``strain_alias``: may be given as ``strain`` instead (stretch = 1 + strain);
- ``value(curve)``: what vlab's run records at each level (vlab.measure.recorder.Curve);
- ``probe``: the factory of its exact sensitivity (vlab.identify.fe_probes: ∂R/∂u · du/dp +
  ∂R/∂f · df/dp), ``axis`` the loading axis it reads;
- ``units``: {name: factor to the solver's unit} (N, N·mm, MPa) of a reading, or None;
- ``needs(scene)``: why the scene does not record it (a shape, an option), or None.
``stability(d, raw)`` gives the homogeneous paths (and stretch ranges) on which the fitted card's
Drucker stability is judged, with the basis; ``closed_form(d, raw)`` the same readings as a data
set of a closed-form kind (``closed_form(d, raw, area0)``: a dict of the Dataset's kind, a, b, y,
extra; area0 the channels' load-cell sections) for the comparison fit.json shows, or None;
``check(scene)`` refuses a scene the kind's readings cannot be differentiated on;
``closed_form_has_K`` False where that closed form is incompressible (K is then held, not compared).

A new kind is one entry here (and its probes in vlab.identify.fe_probes).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from vlab.fields import SceneError
from vlab.identify import fe_probes as pr
from vlab.identify.datasets import FORCE_UNITS, STRESS_UNITS

__all__ = ["Quantity", "Channel", "SpecimenKind", "SPECIMEN_KINDS", "channels_of", "quantities"]

TORQUE_UNITS = {"N*mm": 1.0, "N*m": 1e3}


@dataclass(frozen=True)
class Quantity:
    key: str
    what: str
    value: Callable
    probe: Callable = pr.prescribed
    axis: int = 0
    units: dict | None = None
    strain_alias: bool = False
    needs: Callable = lambda scene: None


@dataclass(frozen=True)
class Channel:
    controls: tuple[Quantity, ...]
    readings: tuple[Quantity, ...]
    optional: bool = False


@dataclass(frozen=True)
class SpecimenKind:
    name: str
    channels: tuple[Channel, ...]
    stability: Callable
    closed_form: Callable = lambda d, raw, area0: None
    check: Callable = lambda scene: None
    closed_form_has_K: bool = True

    def quantity(self, key: str, scene=None) -> Quantity:
        """The quantity of data column ``key`` this scene records (the first whose needs pass)."""
        found = [q for c in self.channels for q in c.controls + c.readings if q.key == key]
        ok = [q for q in found if scene is None or q.needs(scene) is None]
        return (ok or found)[0]


def _option(scene, key: str, default: str) -> str:
    return scene.test.option(key) or default


def _shape(*shapes: str, what: str):
    def needs(scene):
        shape = scene.specimen.shape
        return None if shape in shapes else f"{what} is read on a {' or '.join(shapes)}, not on a {shape}"
    return needs


# ---- the quantities -----------------------------------------------------------------------------------
STRAIN = Quantity("strain", "extensometer strain (1)", lambda c: c.strain[0], pr.extensometer)
FORCE = Quantity("force", "load cell (N)", lambda c: c.force[0], pr.load_cell, units=FORCE_UNITS)
STRAIN2 = Quantity("strain2", "second extensometer's strain (1)", lambda c: c.strain[1], pr.extensometer, axis=1)
FORCE2 = Quantity("force2", "second load cell (N)", lambda c: c.force[1], pr.load_cell, axis=1, units=FORCE_UNITS)

TWIST = Quantity("twist", "twist per unit length ψ (rad/mm)", lambda c: c.stretch[0])
TORQUE = Quantity("torque", "torque about the axis (N·mm)", lambda c: c.extra["torque"], pr.torque,
                  units=TORQUE_UNITS)
AXIAL_FORCE = Quantity(
    "axial_force", "axial force (N, tension > 0)", lambda c: c.force[0], pr.load_cell, units=FORCE_UNITS,
    needs=lambda s: None if _option(s, "axial", "fixed") == "fixed" else
    "axial_force is read with the length held (test.axial = \"fixed\"); a free end reads axial_stretch")
AXIAL_STRETCH = Quantity(
    "axial_stretch", "the free end's axial stretch (1)", lambda c: c.extra["axial_stretch"], pr.end_stretch,
    needs=lambda s: None if _option(s, "axial", "fixed") == "free" else
    "axial_stretch is read on a free end (test.axial = \"free\"); a held length reads axial_force")

PLATEN = Quantity("stretch", "platen stretch λ (1)", lambda c: c.stretch[0], strain_alias=True)
DIE_STRESS = Quantity("stress", "axial nominal stress F/A0 (MPa)", lambda c: c.column("stress", 0),
                      pr.scaled(pr.load_cell, lambda prep, a: 1.0 / prep.specimen.area0[a]), units=STRESS_UNITS)

SPHERE = _shape("sphere-shell", what="the cavity's prescribed stretch")
MEMBRANE = _shape("membrane", what="this bulge reading")
CAVITY_STRETCH = Quantity(
    "stretch", "inner hoop stretch λ_a (1)", lambda c: c.stretch[0], strain_alias=True,
    needs=lambda s: SPHERE(s) and f"{SPHERE(s)}; a membrane's pole stretch is not a control here: give "
                                  "pole_height or volume_ratio")
CAVITY_VOLUME = Quantity("volume_ratio", "cavity volume ratio λ_a³ (1)", lambda c: np.asarray(c.stretch[0]) ** 3,
                         needs=SPHERE)
BULGE_VOLUME = Quantity("volume_ratio", "chamber volume ratio (V0 + V)/V0 (1)", lambda c: c.extra["volume_ratio"],
                        pr.liquid_volume_ratio, needs=MEMBRANE)
POLE_HEIGHT = Quantity("pole_height", "pole height (mm)", lambda c: c.extra["pole_height"], pr.pole_height,
                       needs=MEMBRANE)
CAVITY_PRESSURE = Quantity("pressure", "cavity pressure (MPa)", lambda c: c.extra["pressure"], pr.cavity_pressure,
                           units=STRESS_UNITS, needs=SPHERE)
BULGE_PRESSURE = Quantity("pressure", "liquid pressure (MPa)", lambda c: c.extra["pressure"], pr.liquid_pressure,
                          units=STRESS_UNITS, needs=MEMBRANE)


# ---- the Drucker-stability paths of each kind's data ----------------------------------------------------
def _extension_paths(d, raw):
    strain = np.concatenate([d.a, d.b]) if d.b is not None else np.asarray(d.a)
    span = (1.0 + min(0.0, float(np.min(strain))), 1.0 + float(np.max(strain)))
    paths = {"uniaxial": span} | ({"equibiaxial": span} if d.b is not None else {})
    return paths, ("stretch = 1 + extensometer strain on the uniaxial path"
                   + ("; two-axis readings also on the equibiaxial path" if d.b is not None else ""))


def _torsion_paths(d, raw):
    """At radius r a simple shear γ = ψ r: principal stretches λ± = √(1 + γ²/4) ± γ/2, λ3 = 1,
    those of pure shear (planar) at λ₊; judged up to the surface, γ = ψ_max a."""
    g = float(np.max(np.abs(d.a))) * float(raw["specimen"]["radius"])
    return {"planar": (1.0, float(np.sqrt(1 + g * g / 4) + g / 2))}, (
        "torsion: the surface's simple shear γ = ψ a as pure shear (planar) at λ = √(1 + γ²/4) + γ/2")


def _die_paths(d, raw):
    """F = diag(λ, 1, 1): its isochoric part J^(−1/3) F is uniaxial at λ^(2/3)."""
    lam = np.asarray(d.a, float) ** (2.0 / 3.0)
    return {"uniaxial": (float(min(lam.min(), 1.0)), float(max(lam.max(), 1.0)))}, (
        "confined compression: the isochoric part of diag(λ, 1, 1), uniaxial at λ^(2/3)")


def _cap_stretch(v, a):
    """The mean meridian stretch of a spherical cap through the rim r = a enclosing (v − 1) π a³:
    V = π h (3a² + h²)/6 gives h, then R_c = (a² + h²)/(2h), half-angle θ = 2 atan(h/a), λ = R_c θ / a."""
    h = np.array([np.real(np.roots([1.0, 0.0, 3 * a * a, -6 * a**3 * (x - 1.0)])).max() for x in v])
    return np.where(h > 0, (a * a + h * h) / (2 * np.maximum(h, 1e-300)) * 2 * np.arctan(h / a) / a, 1.0)


def _inflation_paths(d, raw):
    key = d.extra["channels"][0][0]
    x = np.asarray(d.a, float)
    if raw["specimen"]["shape"] == "membrane":
        a = float(raw["specimen"]["radius"])
        v = 1.0 + np.pi * x * (3 * a * a + x * x) / (6 * np.pi * a**3) if key == "pole_height" else x
        lam, basis = _cap_stretch(v, a), "the bulge's pole as equibiaxial at the spherical cap's mean meridian stretch"
    else:
        lam, basis = (x ** (1.0 / 3.0) if key == "volume_ratio" else x), "the inner wall's equibiaxial stretch λ_a"
    return {"equibiaxial": (1.0, float(max(1.0, lam.max())))}, f"inflation: {basis}"


# ---- closed-form kinds of the same readings (fit.json -> fe.homogeneous_fit) --------------------------
def _extension_closed_form(d, raw, area0):
    """stress = F/A0 against stretch = 1 + e in the scene's kind; a cruciform needs both axes."""
    kind, two = raw["test"]["kind"], d.b is not None
    if kind == "biaxial" and not two:
        return None  # one axis of a cruciform has no closed form of its own
    n = d.points
    y = np.r_[d.y[:n] / area0[0], d.y[n:] / area0[1]] if two else d.y / area0[0]
    return {"kind": kind, "a": 1.0 + d.a, "b": None if not two else 1.0 + d.b, "y": y, "extra": None}


def _torsion_closed_form(d, raw, area0):
    """Rivlin's cylinder of the scene's radius: kind "torsion" (torque, axial force, length held) or
    "free-end-torsion" (axial strain λ − 1 then torque, a free end)."""
    geometry = {"radius": float(raw["specimen"]["radius"])}
    n, keys = d.points, [r for _, r in d.extra["channels"]]
    if keys[-1] == "axial_stretch":
        return {"kind": "free-end-torsion", "a": np.asarray(d.a), "b": None, "y": np.r_[d.y[n:] - 1.0, d.y[:n]],
                "extra": {"geometry": geometry, "outputs": ("axial_strain", "torque")}}
    return {"kind": "torsion", "a": np.asarray(d.a), "b": None, "y": np.asarray(d.y),
            "extra": {"geometry": geometry, "outputs": tuple(keys)}}


def _inflation_closed_form(d, raw, area0):
    if raw["specimen"]["shape"] != "sphere-shell" or d.extra["channels"][0][0] != "stretch":
        return None
    s = raw["specimen"]
    return {"kind": "inflation", "a": np.asarray(d.a), "b": None, "y": np.asarray(d.y),
            "extra": {"geometry": {"inner_radius": float(s["inner_radius"]), "thickness": float(s["thickness"])},
                      "outputs": ("pressure",)}}


def _die_closed_form(d, raw, area0):
    return {"kind": "confined-compression", "a": np.asarray(d.a), "b": None, "y": np.asarray(d.y),
            "extra": {"geometry": {}, "outputs": ("stress",)}}


def _volume_controlled(scene):
    if _option(scene, "control", "volume") != "volume":
        raise SceneError("fe.scene: test.control must be \"volume\" for an FE-in-the-loop inflation fit (the "
                         "pressure is then a reading whose sensitivity is exact); got test.control = "
                         f"{scene.test.option('control')!r}")


_EXTENSION = Channel((STRAIN,), (FORCE,))
SPECIMEN_KINDS = {
    "uniaxial": SpecimenKind("uniaxial", (_EXTENSION,), _extension_paths, _extension_closed_form),
    "planar": SpecimenKind("planar", (_EXTENSION,), _extension_paths, _extension_closed_form),
    "biaxial": SpecimenKind("biaxial", (_EXTENSION, Channel((STRAIN2,), (FORCE2,), True)), _extension_paths,
                            _extension_closed_form),
    "torsion": SpecimenKind("torsion", (Channel((TWIST,), (TORQUE,)),
                                        Channel((TWIST,), (AXIAL_FORCE, AXIAL_STRETCH), True)),
                            _torsion_paths, _torsion_closed_form, closed_form_has_K=False),
    "confined-compression": SpecimenKind("confined-compression", (Channel((PLATEN,), (DIE_STRESS,)),),
                                         _die_paths, _die_closed_form),
    "inflation": SpecimenKind("inflation", (Channel((CAVITY_STRETCH, CAVITY_VOLUME, BULGE_VOLUME, POLE_HEIGHT),
                                                    (CAVITY_PRESSURE, BULGE_PRESSURE)),),
                              _inflation_paths, _inflation_closed_form, _volume_controlled, closed_form_has_K=False),
}


def channels_of(fe: dict) -> tuple[tuple[str, str], ...]:
    """The (control key, reading key) of every channel the fit matches: fe["channels"], or those
    of a load cell and extensometer per loading axis (fe["axes"]) of an extension test."""
    if fe.get("channels"):
        return tuple(tuple(c) for c in fe["channels"])
    return tuple((("strain", "force"), ("strain2", "force2"))[a] for a in fe.get("axes", (0,)))


def quantities(fe: dict, scene) -> list[tuple[Quantity, Quantity]]:
    """(control, reading) Quantity of every channel of the fit's (parsed) scene (channels_of)."""
    kind = SPECIMEN_KINDS[scene.test.kind]
    return [(kind.quantity(c, scene), kind.quantity(r, scene)) for c, r in channels_of(fe)]
