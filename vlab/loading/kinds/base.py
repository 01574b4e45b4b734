"""The TestKind contract (vlab/loading/kinds/__init__.py) and what stretch-driven kinds share.

A stretch-driven kind moves grips along the axes in ``axes``: the grip stretch at load parameter t
is λ_a(t) = 1 + t (λ_a − 1) (λ_a the scene's ``stretch``), each grip's travel (λ_a − 1) L_grip
(vlab.loading.grips). Its load cells read the moving grips' reactions, its extensometers the gauge
marks along each loaded axis.
"""

from __future__ import annotations

from typing import Any, Callable

from vlab import fields
from vlab.fields import SceneError

__all__ = ["MIN_STRAIN", "TestKind", "LoadFromZero", "stretch_value", "strain_bound", "PlotSpec", "relative_error"]

STRETCH_RANGE = (0.2, 10.0)  # grip stretches a scene may ask for
# The smallest deformation a load may ask for, |λ − 1|, |γ| or the surface shear of a twist: the
# deformation gradient is I + ∇u in double precision (unit round-off 1.1e-16 beside the 1s of I),
# so a strain of 1e-9 keeps 7 significant digits (the 6 vlab reports) and one of 1e-16 is lost
# whole (1 + 1e-300 is exactly 1): the energies and the load path Q ~ strain² then underflow,
# and a test so small reads noise, or a "limit point" that is none.
MIN_STRAIN = 1e-9


def strain_bound(what: str) -> str:
    """Why MIN_STRAIN, for an error message about ``what`` (e.g. "|test.shear|")."""
    return (f"{what} must be >= {MIN_STRAIN:g} (a smaller deformation is not resolvable in double "
            f"precision beside the 1 of I + ∇u: it keeps fewer than 7 digits)")


def stretch_value(field: str, v: Any) -> float:
    """A grip stretch in the allowed range 0.2..10, 1 or at least MIN_STRAIN away from it
    (SceneError naming ``field`` otherwise)."""
    v = fields.number(field, v, note=" (allowed 0.2..10)")
    if v <= 0:
        raise SceneError(f"{field} must be > 0 (allowed 0.2..10), got {v:g}")
    if not STRETCH_RANGE[0] <= v <= STRETCH_RANGE[1]:
        raise SceneError(f"{field} must be in the allowed range 0.2..10, got {v:g}")
    if v != 1.0 and abs(v - 1.0) < MIN_STRAIN:
        raise SceneError(f"{strain_bound(f'|{field} − 1|')} or 0 (a held axis), got {v!r}")
    return v


def relative_error(measured, reference, scale: float | None = None) -> float:
    """max |measured − reference| / max |reference| over the common rows, or / ``scale`` when
    given (the largest reference stress of any axis: an axis whose stress passes through zero,
    or stays there, σ_y ≡ 0 when ε_y = −ν ε_x, has no scale of its own)."""
    import numpy as np

    n = min(len(measured), len(reference))
    if n == 0:
        return float("nan")
    m, r = np.asarray(measured[:n]), np.asarray(reference[:n])
    denominator = np.max(np.abs(r)) if scale is None else scale
    return float(np.max(np.abs(m - r)) / max(denominator, 1e-300))


class PlotSpec:
    """The report's main plot of a kind: results.json curve columns and axis labels."""

    def __init__(self, x: str, y: str, xlabel: str, ylabel: str, series: tuple[tuple[str, str, str], ...],
                 reference_x: str = "stretch"):
        self.x, self.y, self.xlabel, self.ylabel = x, y, xlabel, ylabel
        self.series = series  # (x column, y column, reference key in results.json → reference)
        self.reference_x = reference_x  # the curve column the reference rows are read at


class TestKind:
    """Base of every kind; the defaults are those of a stretch-driven test (module docstring)."""

    __test__ = False  # not a pytest class
    name = ""
    load_key = "stretch"
    rest = 1.0  # the control column's value at rest (a stretch 1; a shear γ or a twist ψ: 0)
    control_name = "grip stretch"  # what the renders' titles call the control value (vlab.post.snapshot)
    render_field = "von-mises"  # the renders' default colouring (vlab.post.fields.FIELDS)
    axes: tuple[int, ...] = (0,)
    oracle_setups: dict[str, str] = {}  # specimen shape -> grips on which ``state`` is the exact answer
    cyclic = False  # may run test.protocol = "cyclic"
    effects = False  # may carry [effects]
    symmetric = True  # a mirror-symmetric specimen may be reduced ([mesh] symmetry)
    lateral_ratio = False  # the report's lateral-strain plot and apparent Poisson's ratio mean something
    plot: PlotSpec
    force_column, control_column = "force", "stretch"  # results.json → curve: load cell, control value
    measures_E = True  # measures Young's modulus (and ν): the report's E and ν rows mean something
    proportional = True  # u_p(t) = t · û_p (False: the loading's own path, e.g. a rotating grip)
    homogeneous = True  # ``state`` exists (False: torsion, whose shear grows with the radius)
    option_keys: dict[str, tuple[str, ...]] = {}  # the kind's own [test] choice keys: allowed values, default first
    extra_load_keys: tuple[str, ...] = ()  # load keys besides ``load_key`` that ``load_key_for`` may choose
    alternative_load_keys: dict[str, str] = {}  # a key the load may be given as instead -> the key it replaces
    own_number_keys: tuple[str, ...] = ()  # [test] numbers besides the load (torsion: "stretch", its pre-stretch)
    doc = ""

    # --- grammar -------------------------------------------------------------------------------
    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        raise NotImplementedError

    def check(self, test, effects: dict) -> None:
        """Refuse what this kind cannot run (SceneError naming the field); a creep force and an
        imperfection (uniaxial only) are refused where their keys are parsed (vlab/scene/test.py)."""
        if effects and not self.effects:
            name = f"effects.{next(iter(effects))}"
            from vlab.loading.kinds import KINDS

            allowed = ", ".join(k.name for k in KINDS.values() if k.effects)
            raise SceneError(f"{name}: [effects] are not available with test.kind = {self.name!r} in this "
                             f"build (they are with test.kind = {allowed})")

    def check_specimen(self, test, specimen) -> None:
        """Refuse a load the specimen's dimensions make too large (SceneError naming the field);
        most kinds' loads are dimensionless and need nothing here."""

    def load_key_for(self, shape: str, options: dict[str, str]) -> str:
        """The [test] key of the load on specimen ``shape`` with the kind's ``options`` (its
        option_keys as given): ``load_key`` unless the kind says otherwise."""
        return self.load_key

    def control_label(self, test, shape: str) -> str:
        """What the renders' titles call the control value of ``test`` on ``shape``:
        ``control_name`` unless the kind's load key depends on the shape or a control option."""
        return self.control_name

    def parse_own_numbers(self, t: fields.Table, options: dict[str, str]) -> tuple[float, ...]:
        """The kind's ``own_number_keys`` as TestSpec.stretch (a stretch kind's is its load: ())."""
        return ()

    def converted_load(self, key: str, values: tuple[float, ...], specimen) -> tuple[float, ...]:
        """The targets of a load given as the alternative ``key`` (``alternative_load_keys``), in the
        units of ``load_key``, for the parsed ``specimen`` spec (its dimensions)."""
        return values

    def for_test(self, test) -> "TestKind":
        """The kind that runs ``test``: this one, or its variant for the test's options (a
        pressure-controlled inflation's control value is the pressure, not a stretch)."""
        return self

    # --- grips ---------------------------------------------------------------------------------
    def at(self, targets: tuple[float, ...], t: float) -> list[float]:
        """Control values at load parameter t: grip stretches λ(t) = 1 + t (λ − 1)."""
        return [1.0 + t * (s - 1.0) for s in targets]

    def grip_strain(self, targets: tuple[float, ...]) -> tuple[float, ...]:
        """Grip strain at t = 1 per control (λ − 1): what schedules and rates count."""
        return tuple(s - 1.0 for s in targets)

    def scheduled(self, levels, test, specimen):
        """The protocol's ``levels`` (vlab.loading.protocol.Levels) as this kind runs them on the
        ``specimen`` spec: as they are, unless the kind runs a phase of its own before them
        (tension–torsion's stretch) or needs finer levels somewhere (a bulge's first ones)."""
        return levels

    def grip_stretches(self, targets: tuple[float, ...]) -> tuple[float, ...]:
        """The grip stretch of every axis the grips move or hold (vlab.loading.grips)."""
        return tuple(targets)

    def describe(self, values) -> str:
        """The control values in words, named (messages print no other name beside it)."""
        return "stretch " + ", ".join(f"{s:.4g}" for s in values)

    def loading(self, specimen, X, test):
        from vlab.loading.grips import grip_loading

        return grip_loading(specimen, X, self.grip_stretches(test.targets), test.grips)

    def fixtures(self, specimen) -> tuple:
        """The rigid fixtures of the test that the renders draw around the meshed ``specimen``
        (vlab.geometry.fixtures.Part: a die, its platens); none unless the kind has some."""
        return ()

    def isochoric(self, values):
        """The isochoric (incompressible) deformation gradient (3, 3) at control values ``values``:
        the path a locking limit is checked on (vlab.materials.card.check_path)."""
        raise NotImplementedError

    def locking_path(self, test, specimen) -> tuple[str, Callable[[float], Any]]:
        """(the [test] key the load was given as, s ↦ the isochoric F (3, 3) at load fraction s):
        what a locking limit is checked on (vlab.materials.card.check_path). ``specimen`` is the
        parsed shape spec (its dimensions). The control values map to F through ``isochoric``;
        a kind whose control is not a stretch of the material (a volume, a twist) says how."""
        key = self.load_key_for(specimen.shape, dict(test.options))
        return key, lambda s: self.isochoric(self.at(test.targets, s))

    def has_state(self, shape: str) -> bool:
        """Whether ``state`` of the control values is the material's state on ``shape`` (what the
        admissibility check reads): ``homogeneous`` unless the kind says otherwise."""
        return self.homogeneous

    def has_oracle(self, shape: str, grips: str) -> bool:
        return self.oracle_setups.get(shape) == grips

    # --- oracle --------------------------------------------------------------------------------
    def state(self, material, values):
        raise NotImplementedError

    def reference(self, material, curve) -> dict:
        """The oracle's nominal stress per loaded axis and lateral stretch at the recorded rows,
        with the largest relative error of the load-cell stress against it."""
        from vlab.materials.homogeneous import InadmissibleState

        out: dict = {f"stress_{'xy'[a]}": [] for a in self.axes} | {"lateral_stretch": []}
        try:
            for row in zip(*(curve.stretch[a] for a in self.axes)):
                state = self.state(material, row)
                for a in self.axes:
                    out[f"stress_{'xy'[a]}"].append(float(state.P[a, a]))
                out["lateral_stretch"].append(float(state.lateral_stretch))
        except InadmissibleState as exc:
            out["note"] = str(exc)
        # relative to the largest stress of any axis: an axis whose stress passes through or stays
        # at zero (σ_y ≡ 0 when ε_y = −ν ε_x) has no scale of its own
        scale = max((max(map(abs, out[f"stress_{'xy'[a]}"]), default=0.0) for a in self.axes), default=0.0)
        for a in self.axes:
            key = "xy"[a]
            out[f"max_relative_error_{key}"] = relative_error(curve.column("stress", a), out[f"stress_{key}"],
                                                              scale)
        return out

    # --- instruments and measures: declared by name, provided by vlab/measure/kinds.py -----------
    gauge = "extensometers"  # strain instruments: "extensometers" (per loaded axis) | "shear-gauge"
    readers: tuple[str, ...] = ()  # other readings: "normal-force", "centre-cauchy"
    field_probe = "gauge-section"  # results.json → homogeneity: "gauge-section" | "pure-shear" | "simple-shear"
    fit = ""  # the constants measured: "uniaxial" | "biaxial" | "planar" | "shear"
    crosshead_fit: str | None = None  # "crosshead": the modulus from grip strain (uniaxial)

    def columns(self, curve) -> dict[str, list[float]]:
        """results.json → curve: axis 0 unsuffixed, axis 1 suffixed ``_y``."""
        cols: dict[str, list[float]] = {}
        for axis in self.axes:
            sfx = "" if axis == 0 else "_y"
            cols["stretch" + sfx] = list(curve.stretch[axis])
            cols["strain" + sfx] = list(curve.strain[axis])
            cols["stress" + sfx] = list(curve.column("stress", axis))
            cols["force" + sfx] = list(curve.force[axis])
            cols["true_strain" + sfx] = list(curve.column("true_strain", axis))
            cols["true_stress" + sfx] = list(curve.column("true_stress", axis))
        return cols

    measured_units: dict[str, str] = {}  # units of the kind's own measures (results.json → measured)
    units = {"stretch": "1 (grip)", "strain": "1 (extensometer, engineering)",
             "stress": "MPa (engineering)", "force": "N", "true_stress": "MPa",
             "crosshead_strain": "1 (grip separation change / initial grip separation)", "time": "s"}

    def units_of(self, columns: dict) -> dict[str, str]:
        """results.json → curve.units of a record with ``columns`` (a kind whose columns depend on
        the specimen says which units go with which)."""
        return dict(self.units)

    def areas(self, specimen) -> dict[int, float]:
        """Reference area (mm²) each load cell's force is divided by."""
        return {a: specimen.area0[a] for a in self.axes}


class LoadFromZero:
    """A kind mixin for a load that starts at 0 (a shear γ, a twist ψ, a pressure p): the control
    value at load parameter t is t × its target, and the schedule counts the target itself."""

    rest = 0.0

    def at(self, targets, t: float) -> list[float]:
        return [t * targets[0]]

    def grip_strain(self, targets) -> tuple[float, ...]:
        return (targets[0],)
