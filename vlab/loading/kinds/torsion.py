"""Torsion of a cylinder: ``twist = ψ`` (the final twist per unit length, rad/mm, 0 < |ψ| a ≤ 5)
or ``angle`` (the end rotation, degrees: ψ = angle π / (180 L)), ``axial = "fixed"`` (the length
held: the axial force is recorded) or ``"free"`` (the turning end slides along the axis: the
length change is recorded), ``grips = "clamped"``. The end x = 0 is clamped, the end x = L turns by
φ = t ψ L (vlab.loading.torsion).

Records per level: the twist ψ(t) = t ψ (rad/mm), the torque T = Σ (y f_z − z f_y) over the
turning end's reactions in the current configuration (N·mm), the axial force N = Σ f_x (N) and
the axial stretch 1 + ū_x / L (ū_x the mean axial displacement of the turning end).

Oracle (Rivlin 1948, incompressible Mooney–Rivlin W = C10 (I₁ − 3) + C01 (I₂ − 3), length held):
every section turns rigidly, T = π ψ a⁴ (C10 + C01) (linear in ψ at any twist) and
N = −(π/2) ψ² a⁴ (C10 + 2 C01) (compressive: the Poynting effect; with the end free the cylinder
lengthens). A compressible FE model approaches them as K/μ → ∞ and the mesh is refined
(tests/test_torsion.py states the study). Measures the torsional stiffness k = dT/dψ over the
modulus window (ψ in rad/mm) and from it G = k / J_p, J_p = A² / (2π) of the meshed section.

The schedule counts ψ (rad/mm) as its strain (``grip_strain``), so the modulus window's levels
lie at twists in the window.
"""

from __future__ import annotations

import math

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import MIN_STRAIN, LoadFromZero, PlotSpec, TestKind, strain_bound, stretch_value
from vlab.loading.torsion import PHASE_END, tension_torsion

SHEAR_LIMIT = 5.0  # the largest surface shear ψ a a scene may ask for


class Torsion(LoadFromZero, TestKind):
    name = "torsion"
    load_key = "twist"
    rest = 0.0
    control_name = "twist (rad/mm)"
    render_field = "max-shear"  # λ₁ − λ₃: the shear strain γ = ψ r of each section's simple shear
    axes = (0,)
    symmetric = False
    measures_E = False
    proportional = False  # a turning grip: u_p(t) is not t · û_p
    homogeneous = False  # no homogeneous state: the shear is ψ r
    force_column, control_column = "axial_force", "twist"
    plot = PlotSpec("twist", "torque", "twist ψ [rad/mm]", "torque T [N·mm]", (("twist", "torque", "torque"),),
                    reference_x="twist")
    measured_units = {"torsional_stiffness": "N·mm² (torque per twist per unit length)", "G": "MPa",
                      "torque_at_end": "N·mm", "axial_force_at_end": "N", "axial_stretch_at_end": "1"}
    doc = "torsion of a cylinder: one end clamped, the other turned; length held (fixed) or free"
    readers = ("torque",)  # vlab/measure/kinds.py
    option_keys = {"axial": ("fixed", "free"), "sequence": ("stretch-then-twist", "together")}
    alternative_load_keys = {"angle": "twist"}
    own_number_keys = ("stretch",)
    fit = "torsion"
    phased = False  # the pre-stretch ramps with the twist (TensionTorsion: before it)
    units = {"twist": "rad/mm (end rotation / length)", "torque": "N·mm", "axial_force": "N (tension > 0)",
             "axial_stretch": "1 (turning end: 1 + mean u_x / L)", "surface_shear": "1 (twist x radius)",
             "time": "s"}

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        """(ψ,) from ``twist`` (rad/mm), or (the end rotation in degrees,) from ``angle``
        (``converted_load`` makes it ψ)."""
        key, unit = ("angle", "degrees") if "angle" in t.raw else ("twist", "rad/mm")
        field, v = t.field(key), t.get(key)
        if isinstance(v, list):
            raise SceneError(f"{field} must be a single number ({unit}) for kind = 'torsion', got {fields.show(v)}")
        value = fields.number(field, v, note=f" ({unit}, not 0)")
        if value == 0.0:
            raise SceneError(f"{field} must not be 0 (no twist applies no load), in {unit}")
        return (value,)

    def parse_own_numbers(self, t: fields.Table, options: dict[str, str]) -> tuple[float, ...]:
        """(λ₀,): the axial stretch of tension–torsion, ``stretch`` (0.2..10, default 1: none), applied
        before the twist or with it (``sequence``); with the length held only (a free end carries
        no axial load to stretch it)."""
        if "stretch" not in t.raw:
            if "sequence" in t.raw:
                raise SceneError(f"{t.field('sequence')} orders the axial stretch and the twist: it needs "
                                 f"test.stretch (tension–torsion), which is not given")
            return ()
        lam = stretch_value(t.field("stretch"), t.get("stretch"))
        if options.get("axial") == "free":
            raise SceneError(f"{t.field('stretch')} (the axial stretch of tension–torsion) needs test.axial = "
                             f"'fixed' (a free end carries no axial load), got test.axial = 'free'")
        return (lam,) if lam != 1.0 else ()

    def converted_load(self, key: str, values, specimen) -> tuple[float, ...]:
        """ψ = angle π / (180 L) (rad/mm) of the end rotation ``angle`` (degrees) over the length L."""
        return (math.radians(values[0]) / specimen.length,)

    def for_test(self, test) -> TestKind:
        """The stretch-then-twist variant where a pre-stretch is given with that (default) sequence."""
        return TENSION_TORSION if test.stretch and test.option("sequence") == "stretch-then-twist" else self

    def check(self, test, effects: dict) -> None:
        super().check(test, effects)
        if test.grips != "clamped":
            raise SceneError(f"test.grips must be 'clamped' for test.kind = 'torsion' (the axial condition of "
                             f"the turning end is test.axial), got {test.grips!r}")

    def check_specimen(self, test, specimen) -> None:
        """The surface shear ψ a must stay ≤ SHEAR_LIMIT (SceneError naming test.twist)."""
        gamma = abs(test.targets[0]) * specimen.radius
        if gamma < MIN_STRAIN:
            raise SceneError(f"{strain_bound('the surface shear |test.twist| x specimen.radius')} "
                             f"(|test.twist| >= {MIN_STRAIN / specimen.radius:.3g} rad/mm for specimen.radius = "
                             f"{specimen.radius:g} mm), got {test.targets[0]!r}")
        if gamma > SHEAR_LIMIT:
            raise SceneError(f"test.twist (or test.angle / specimen.length) must be <= "
                             f"{SHEAR_LIMIT / specimen.radius:.4g} rad/mm in magnitude for specimen.radius = "
                             f"{specimen.radius:g} mm (surface shear twist x radius <= {SHEAR_LIMIT:g}; an angle "
                             f"<= {math.degrees(SHEAR_LIMIT * specimen.length / specimen.radius):.4g} degrees), "
                             f"got {test.targets[0]:g} rad/mm")

    def describe(self, values) -> str:
        return f"twist {values[0]:.4g} rad/mm"

    def loading(self, specimen, X, test):
        from vlab.loading.torsion import torsion_loading

        return torsion_loading(specimen, X, test.targets[0], test.option("axial"),
                               test.stretch[0] if test.stretch else 1.0, self.phased)

    def isochoric(self, values):
        import numpy as np

        return np.eye(3)  # the twist's surface shear depends on the radius: locking_path has it

    def locking_path(self, test, specimen):
        """The surface r = a, the worst state of the cylinder: with the axial stretch λ(s) and the
        twist ψ(s) (``axial_path``), sections contract by λ^(−1/2) and turn by ψ X, so in the
        (axial, hoop, radial) frame F = [[λ, 0, 0], [ψ a λ^(−1/2), λ^(−1/2), 0], [0, 0, λ^(−1/2)]]
        (det F = 1; Ī₁ = λ² + 2/λ + ψ² a²/λ)."""
        import numpy as np

        lam0 = test.stretch[0] if test.stretch else 1.0
        psi, radius = test.targets[0], specimen.radius

        def path(s: float):
            lam, twist = tension_torsion(lam0, psi, s, self.phased)
            c = lam ** -0.5
            return np.array([[lam, 0.0, 0.0], [twist * radius * c, c, 0.0], [0.0, 0.0, c]])

        return self.load_key, path

    def areas(self, specimen) -> dict[int, float]:
        return {0: specimen.area0[0]}

    def columns(self, curve) -> dict[str, list[float]]:
        radius = math.sqrt(curve.area0[0] / math.pi)  # of the meshed section's area
        return {"twist": list(curve.stretch[0]), "torque": list(curve.extra.get("torque", [])),
                "axial_force": list(curve.force[0]), "axial_stretch": list(curve.extra.get("axial_stretch", [])),
                "surface_shear": [psi * radius for psi in curve.stretch[0]]}


TORSION = Torsion()


class TensionTorsion(Torsion):
    """Tension–torsion as a lab runs it (``sequence = "stretch-then-twist"``, the default with a
    ``stretch``): phase 1, t ≤ t₁ = PHASE_END, stretches to λ₀ at zero twist in ``steps`` levels;
    phase 2 twists at the held λ₀, the protocol's levels τ ∈ (0, 1] (with the modulus window's)
    run at t = t₁ + (1 − t₁) τ, so the twist is ψ(t) = ψ τ (vlab.loading.torsion.tension_torsion)."""

    phased = True
    phase_units = {"phase": "1 (stretch at zero twist) or 2 (twist at the held stretch)"}

    def at(self, targets, t: float) -> list[float]:
        return [tension_torsion(1.0, targets[0], t, True)[1]]

    def scheduled(self, levels, test, specimen):
        """The stretch phase's ``test.steps`` levels, then the protocol's ``levels`` mapped into
        phase 2 (a timed or force-held protocol is refused in ``check``)."""
        from vlab.loading.protocol import Levels

        first = PHASE_END * np.arange(1, test.steps + 1) / test.steps
        t = np.concatenate([first, PHASE_END + (1.0 - PHASE_END) * np.asarray(levels.t)])
        return Levels(t, None, np.zeros(len(t), dtype=bool))

    def check(self, test, effects: dict) -> None:
        super().check(test, effects)
        if test.protocol.timed or test.protocol.force is not None or test.protocol.has_hold:
            raise SceneError(f"test.protocol = {test.protocol.name!r} with a rate, a hold or a force is not "
                             f"available with test.sequence = 'stretch-then-twist' (the stretch phase has no "
                             f"time base); use test.sequence = 'together' or a quasi-static protocol")

    def units_of(self, columns: dict) -> dict[str, str]:
        return super().units_of(columns) | self.phase_units

    def columns(self, curve) -> dict[str, list[float]]:
        return super().columns(curve) | {"phase": [1 if t <= PHASE_END else 2 for t in curve.t]}


TENSION_TORSION = TensionTorsion()
