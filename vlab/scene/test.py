"""``[test]``: kind, grips, stretch, steps, protocol (monotonic, load-unload, cyclic, relaxation,
creep) with its time keys, and a buckling imperfection.

Stretches lie in 0.2..10 (grip stretch; < 1 is compression); steps default to 10; the grips
default to the first the specimen allows. The test-kind registry of vlab.loading replaces the
kind handling here by delegation (issue 17).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.protocol import HOLDS, PROTOCOLS, ProtocolSpec
from vlab.scene.specimen import SPECIMEN_TESTS

__all__ = ["TestSpec", "PROTOCOL_KEYS", "parse_test"]


PROTOCOL_KEYS = ("protocol", "amplitudes", "min_stretch", "strain_rate", "ramp_time", "hold_time",
                 "hold_steps", "force")


@dataclass(frozen=True)
class TestSpec:
    __test__ = False  # not a pytest test class
    kind: str  # "uniaxial" | "biaxial"
    grips: str  # "roller" | "clamped"
    stretch: tuple[float, ...]  # (s,) uniaxial, (sx, sy) biaxial
    steps: int
    protocol: ProtocolSpec = ProtocolSpec()  # vlab.loading.protocol: monotonic unless given
    imperfection: float | None = None  # buckling-mode imperfection, amplitude / thickness


def _stretch_value(field: str, v: Any) -> float:
    v = fields.number(field, v, note=" (allowed 0.2..10)")
    if v <= 0:
        raise SceneError(f"{field} must be > 0 (allowed 0.2..10), got {v:g}")
    if not 0.2 <= v <= 10:
        raise SceneError(f"{field} must be in the allowed range 0.2..10, got {v:g}")
    return v


def parse_test(raw: Any, shape: str = "block") -> TestSpec:
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
