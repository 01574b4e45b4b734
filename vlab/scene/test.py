"""``[test]``: kind, grips, the kind's load (``stretch`` or ``shear``), steps, protocol (monotonic,
load-unload, cyclic, relaxation, creep) with its time keys, a buckling imperfection and a
misaligned load train (``misalignment = {offset = mm, tilt = degrees}``, vlab.loading.misalignment)
and slip in the grips (``grip_slip = mm/N``: the crosshead reads the clamps' travel plus the slip).

The kind comes from the test-kind registry (vlab/loading/kinds/), which parses its own load key:
grip stretches in 0.2..10 (< 1 is compression) for uniaxial, biaxial and planar tests, the amount
of shear |γ| <= 5 for simple shear (a list of rising amplitudes with protocol = "cyclic": fully
reversed cycles). Steps default to 10; the grips default to the first the specimen's shape allows
with that kind (vlab/geometry/shapes.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.protocol import HOLDS, PROTOCOLS, ProtocolSpec
from vlab.geometry.shapes import SHAPES

__all__ = ["TestSpec", "PROTOCOL_KEYS", "GRIP_KINDS", "parse_test"]


PROTOCOL_KEYS = ("protocol", "amplitudes", "min_stretch", "strain_rate", "ramp_time", "hold_time",
                 "hold_steps", "force")
OTHER_KEYS = ("steps", "imperfection", "misalignment", "grip_slip")  # test keys every kind reads
GRIP_KINDS = ("roller", "clamped", "kinematic", "plates", "die", "cavity")  # test.grips


@dataclass(frozen=True)
class TestSpec:
    __test__ = False  # not a pytest test class
    kind: str  # a name in vlab.loading.kinds.KINDS: uniaxial | biaxial | planar | simple-shear
    grips: str  # roller | clamped (stretch kinds); kinematic | plates (simple shear)
    stretch: tuple[float, ...]  # grip stretches at t = 1: (s,) uniaxial, planar; (sx, sy) biaxial; () shear
    steps: int
    protocol: ProtocolSpec = ProtocolSpec()  # vlab.loading.protocol: monotonic unless given
    imperfection: float | None = None  # buckling-mode imperfection, amplitude / thickness
    shear: tuple[float, ...] = ()  # simple shear: (γ,) at t = 1 (cyclic: the largest amplitude)
    twist: tuple[float, ...] = ()  # torsion: (ψ,) at t = 1, rad/mm
    options: tuple[tuple[str, str], ...] = ()  # the kind's own choice keys (TestKind.option_keys), as given
    # (offset_y, offset_z mm, tilt_y, tilt_z degrees) of the moving grip; None: aligned
    misalignment: tuple[float, float, float, float] | None = None
    grip_slip: float = 0.0  # mm/N: the grips' slip compliance, seen by the crosshead only (uniaxial)

    def option(self, key: str) -> str:
        """The value of one of the kind's choice keys (its default when not given)."""
        return dict(self.options)[key]

    @property
    def targets(self) -> tuple[float, ...]:
        """The control values at load parameter t = 1, whatever the kind (its ``load_key``)."""
        return self.shear or self.twist or self.stretch


def parse_test(raw: Any, shape: str = "block", specimen=None) -> TestSpec:
    """[test]: the kind (vlab.loading.kinds) parses its own load key; grips per specimen shape;
    ``specimen`` (the parsed spec) converts a load given by an alternative key (a torsion angle)."""
    from vlab.loading.kinds import KINDS

    load_keys = tuple(dict.fromkeys([k.load_key for k in KINDS.values()]
                                    + [key for k in KINDS.values() for key in k.extra_load_keys]
                                    + [key for k in KINDS.values() for key in k.alternative_load_keys]))
    option_keys = tuple(dict.fromkeys(key for k in KINDS.values() for key in k.option_keys))
    t = fields.Table("test", raw, ("kind", "grips") + load_keys + option_keys + OTHER_KEYS + PROTOCOL_KEYS)
    tests = SHAPES[shape].tests  # the registry now: a shape registered by a script counts
    kind = KINDS[t.choice("kind", tuple(KINDS))]
    if kind.name not in tests:
        raise SceneError(f"{t.field('kind')} must be one of {', '.join(tests)} for specimen.shape = "
                         f"{shape!r}, got {kind.name!r}")
    grips = _grips(t, tests[kind.name], shape, kind.name)
    options = _options(t, kind, option_keys)
    load_key = _load_key(t, kind, shape, options, load_keys)
    protocol_name = t.choice("protocol", PROTOCOLS, default="monotonic")
    if protocol_name == "cyclic" and not kind.cyclic:
        raise SceneError(f"test.protocol = 'cyclic' needs test.kind = "
                         f"{' or '.join(repr(k.name) for k in KINDS.values() if k.cyclic)}, got {kind.name!r}")
    targets = _targets(t, kind, protocol_name, load_key)
    if load_key in kind.alternative_load_keys:
        targets = kind.converted_load(load_key, targets, specimen)
    if load_key == "stretch" and all(s == 1.0 for s in targets):
        raise SceneError(f"{t.field('stretch')} must not be 1 everywhere (a stretch of 1 applies no load), "
                         f"got {fields.show(t.raw['stretch'])}")
    stretch = targets if kind.load_key == "stretch" else kind.parse_own_numbers(t, dict(options))
    return TestSpec(kind=kind.name, grips=grips, stretch=stretch,
                    steps=t.integer("steps", 1, 10000, default=10),
                    protocol=_parse_protocol(t, protocol_name, targets, kind),
                    imperfection=_imperfection(t, kind.name, targets),
                    shear=targets if kind.load_key == "shear" else (),
                    twist=targets if kind.load_key == "twist" else (), options=options,
                    misalignment=_misalignment(t, kind.name, grips, shape), grip_slip=_grip_slip(t, kind.name))


def _grips(t: fields.Table, grip_kinds: tuple[str, ...], shape: str, kind: str) -> str:
    """test.grips: one of the shape's grips for this kind (the first is the default)."""
    grips = t.choice("grips", GRIP_KINDS, default=grip_kinds[0])
    if grips not in grip_kinds:
        raise SceneError(f"{t.field('grips')} must be one of {', '.join(grip_kinds)} for specimen.shape = "
                         f"{shape!r} with test.kind = {kind!r}, got {grips!r}")
    return grips


def _load_key(t: fields.Table, kind, shape: str, options, load_keys: tuple[str, ...]) -> str:
    """The key the scene gives its load in: the kind's for this shape and options, or one
    alternative of it (not both); any other kind's load key is refused naming its kinds."""
    from vlab.loading.kinds import KINDS

    load_key = kind.load_key_for(shape, dict(options))
    given = [key for key in (load_key, *(a for a, b in kind.alternative_load_keys.items() if b == load_key))
             if key in t.raw]
    if len(given) > 1:
        raise SceneError(f"give one of {' or '.join(f'test.{k}' for k in given)} for test.kind = {kind.name!r}, "
                         f"not both")
    load_key = given[0] if given else load_key
    for key in load_keys:
        if key != load_key and key in t.raw and key not in kind.own_number_keys:
            if key in (kind.load_key, *kind.extra_load_keys):  # this kind's, on another shape or control
                given = "".join(f", test.{k} = {v!r}" for k, v in options)
                raise SceneError(f"{t.field(key)} is not the load of test.kind = {kind.name!r} on specimen.shape = "
                                 f"{shape!r}{given}: give test.{load_key}")
            owners = " or ".join(repr(k.name) for k in KINDS.values()
                                 if key in (k.load_key, *k.extra_load_keys, *k.alternative_load_keys))
            raise SceneError(f"{t.field(key)} applies to test.kind = {owners}, not {kind.name!r}; "
                             f"give test.{load_key}")
    return load_key


def _options(t: fields.Table, kind, option_keys: tuple[str, ...]) -> tuple[tuple[str, str], ...]:
    """The kind's own choice keys (``option_keys``: key -> (allowed values, the first the
    default)); another kind's key is an error naming it and the kinds it applies to."""
    from vlab.loading.kinds import KINDS

    for key in option_keys:
        if key not in kind.option_keys and key in t.raw:
            owners = " or ".join(repr(k.name) for k in KINDS.values() if key in k.option_keys)
            raise SceneError(f"{t.field(key)} applies to test.kind = {owners}, not {kind.name!r}")
    return tuple((key, t.choice(key, allowed, default=allowed[0])) for key, allowed in kind.option_keys.items())


def _targets(t: fields.Table, kind, protocol_name: str, load_key: str) -> tuple[float, ...]:
    """The kind's load at t = 1 (given as ``load_key``, the shape's); a stretch-driven cyclic test
    peaks at its largest amplitude."""
    if protocol_name != "cyclic" or kind.load_key != "stretch":
        if "amplitudes" in t.raw and protocol_name == "cyclic":
            raise SceneError(f"{t.field('amplitudes')} is for stretch-driven cycles; with test.kind = "
                             f"{kind.name!r} give the amplitudes as test.{kind.load_key} = [..]")
        t.get(load_key)  # a missing key is an error naming it
        return kind.parse_load(t, protocol_name)
    amplitudes = _amplitudes(t)
    if "stretch" in t.raw:
        raise SceneError(f"{t.field('stretch')} is not used with test.protocol = 'cyclic' (the largest of "
                         f"test.amplitudes is the peak stretch); remove it, got {fields.show(t.raw['stretch'])}")
    return (amplitudes[-1],)


def _amplitudes(t: fields.Table) -> tuple[float, ...]:
    from vlab.loading.kinds.base import stretch_value

    field, v = t.field("amplitudes"), t.get("amplitudes")
    if not isinstance(v, list) or not 1 <= len(v) <= 50:
        raise SceneError(f"{field} must be a list of 1..50 peak grip stretches, got {fields.show(v)}")
    amps = tuple(stretch_value(f"{field}[{i}]", x) for i, x in enumerate(v))
    side = [a > 1.0 for a in amps]
    growing = all(abs(b - 1.0) > abs(a - 1.0) for a, b in zip(amps, amps[1:]))
    if 1.0 in amps or len(set(side)) > 1 or not growing:
        raise SceneError(f"{field} must move away from 1 on one side with every cycle (rising "
                         f"amplitudes, all > 1 or all < 1), got {list(amps)}")
    return amps


def _parse_protocol(t: fields.Table, name: str, stretch: tuple[float, ...], kind) -> ProtocolSpec:
    """The [test] protocol keys: each allowed only for the protocols that use it."""
    reversed_cycles = name == "cyclic" and kind.load_key != "stretch"  # the kind's own load, 0 -> a -> -a
    if reversed_cycles and "min_stretch" in t.raw:
        raise SceneError(f"{t.field('min_stretch')} is for stretch-driven cycles; test.kind = {kind.name!r} "
                         f"cycles fully reversed, 0 -> a -> -a -> ...")
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
    amplitudes = tuple(t.raw.get("amplitudes", ())) if name == "cyclic" else ()
    return ProtocolSpec(
        name=name, amplitudes=kind.amplitudes(t) if reversed_cycles else amplitudes,
        min_stretch=min_stretch, reversed=reversed_cycles,
        strain_rate=t.number("strain_rate", default=None, gt=0, le=1e4, note=" 1/s"),
        ramp_time=t.number("ramp_time", default=None, gt=0, le=1e9, note=" s"),
        hold_time=t.number("hold_time", gt=0, le=1e9, note=" s") if name in HOLDS else 0.0,
        hold_steps=t.integer("hold_steps", 1, 10000, default=20),
        force=_creep_force(t, stretch, kind.name) if name == "creep" else None)


def _creep_force(t: fields.Table, stretch: tuple[float, ...], kind: str) -> float | None:
    """test.force (N): the creep load, ramped under force control over test.ramp_time, then held.
    Its sign follows test.stretch (which then only gives the direction and scale of the grip
    travel): > 0 in tension (stretch > 1), < 0 in compression."""
    if "force" not in t.raw:
        return None
    if "ramp_time" not in t.raw:
        raise SceneError(f"{t.field('force')} is ramped under force control: give test.ramp_time (s), "
                         "the time to reach it (test.strain_rate sets a grip speed, not a load rate)")
    if kind != "uniaxial":
        raise SceneError(f"{t.field('force')} needs test.kind = 'uniaxial'")
    if stretch[0] > 1.0:
        return t.number("force", gt=0, le=1e9, note=" N, tension as test.stretch > 1")
    return t.number("force", ge=-1e9, lt=0, note=" N, compression as test.stretch < 1")


def _imperfection(t: fields.Table, kind: str, stretch: tuple[float, ...]) -> float | None:
    """``[test] imperfection``: amplitude of the buckling-mode imperfection / specimen thickness,
    0 < a <= 0.5, for uniaxial compression only (a tension test has no buckling mode)."""
    if "imperfection" not in t.raw:
        return None
    value = t.number("imperfection", gt=0, le=0.5, note=" (amplitude / specimen thickness)")
    if kind != "uniaxial":  # cite the kind, not a load key it does not have (a shear, a twist)
        raise SceneError(f"{t.field('imperfection')} applies to uniaxial compression (test.kind = 'uniaxial' "
                         f"with test.stretch < 1), got test.kind = {kind!r}")
    if stretch[0] >= 1.0:
        raise SceneError(f"{t.field('imperfection')} applies to uniaxial compression (test.stretch < 1), "
                         f"got test.stretch = {list(stretch)}")
    return value


MISALIGNED_SHAPES = ("block", "dogbone")  # a thickness along z whose faces carry the strain gauges


def _misalignment(t: fields.Table, kind: str, grips: str, shape: str) -> tuple[float, float, float, float] | None:
    """``[test] misalignment = {offset = [e_y, e_z], tilt = [θ_y, θ_z]}``: the moving grip's offset
    (mm, along the width y and the thickness z, any sign) and tilt (degrees about y, bending in the
    thickness plane, and about z, bending in the width plane; each |θ| < 90) of the load axis
    (vlab.loading.misalignment), for a uniaxial test of a block or dogbone in clamped grips (a
    roller grip prescribes no lateral motion to misalign). A single number is the thickness
    plane's: ``offset = e`` is e_z, ``tilt = θ`` is θ_y."""
    if "misalignment" not in t.raw:
        return None
    field, raw = t.field("misalignment"), t.raw["misalignment"]
    if kind != "uniaxial" or grips != "clamped" or shape not in MISALIGNED_SHAPES:
        raise SceneError(f"{field} applies to a uniaxial test in clamped grips (test.grips = 'clamped') of a "
                         f"{' or '.join(MISALIGNED_SHAPES)}; got test.kind = {kind!r}, test.grips = {grips!r}, "
                         f"specimen.shape = {shape!r}")
    m = fields.Table(field, raw, ("offset", "tilt"))
    e_y, e_z = _pair(m, "offset", "[e_y, e_z]", dict(ge=-1e3, le=1e3, note=" (mm)"))
    th_y, th_z = _pair(m, "tilt", "[theta_y, theta_z]", dict(gt=-90.0, lt=90.0, note=" (degrees)"))
    return e_y, e_z, th_y, th_z


#: a number given for the offset or the tilt is the thickness plane's component: the second of
#: [e_y, e_z], the first of [θ_y, θ_z]
THICKNESS_INDEX = {"offset": 1, "tilt": 0}


def misalignment_pair(key: str, value) -> tuple[float, float]:
    """test.misalignment's ``key`` ("offset" or "tilt") as its two components, a number being the
    thickness plane's (THICKNESS_INDEX)."""
    if isinstance(value, (list, tuple)):
        return float(value[0]), float(value[1])
    out = [0.0, 0.0]
    out[THICKNESS_INDEX[key]] = float(value)
    return out[0], out[1]


def _pair(m: fields.Table, key: str, what: str, limits: dict) -> tuple[float, float]:
    """The validated ``key``: a number or a list of two, each within ``limits``; (0, 0) if absent."""
    raw = m.raw.get(key, 0.0)
    if isinstance(raw, list):
        return fields.vector(m.field(key), raw, 2, what, **limits)
    return misalignment_pair(key, m.number(key, 0.0, **limits))


def _grip_slip(t: fields.Table, kind: str) -> float:
    """``[test] grip_slip = C`` (mm/N, >= 0): the specimen slips in the grips by C·F, so the crosshead
    reads the clamps' travel plus C·F (vlab.measure.recorder.Curve.crosshead_strain); uniaxial only."""
    if "grip_slip" not in t.raw:
        return 0.0
    if kind != "uniaxial":
        raise SceneError(f"{t.field('grip_slip')} applies to test.kind = 'uniaxial' (the crosshead modulus), "
                         f"got {kind!r}")
    return t.number("grip_slip", 0.0, ge=0.0, le=10.0, note=" (mm/N, the grips' slip compliance)")
