"""Simple shear: ``shear = γ`` (the amount of shear, |γ| ≤ 5, ≠ 0), or with
``protocol = "cyclic"`` a list of rising amplitudes [γ₁, γ₂, …] (> 0), each run as a fully
reversed cycle 0 → γ₁ → −γ₁ → γ₂ → −γ₂ → … → 0.

Two set-ups (grips):
- ``kinematic`` on a block: the whole boundary follows x = X + γ Y e₁ (u = (γ Y, 0, 0)), so the
  state is homogeneous, F = I + γ e₁⊗e₂ (materials.homogeneous.simple_shear, the oracle with its
  Poynting normal stresses); the top face y = W is the moving plate.
- ``plates`` on a shear specimen (geometry/shear.py): a block bonded between rigid plates, the
  plate y = 0 held, the plate y = H moved tangentially by γ H along x with the normal gap held
  (u_y = u_z = 0 on both); the free faces give the edge effects a lab sees.

Instruments: the shear force F_s (x reaction) and the normal force F_n (y reaction) on the moving
plate (load cells), the shear strain from the plate travel γ = Δx / H and from gauge marks on the
free face z = D, γ_g = (u_x(b) − u_x(a)) / (Y_b − Y_a) (measure/instruments.py ShearGauge), and
(with a continuum material) the Cauchy stress averaged over the centre region from the FE field.
Nominal stresses per plate area A₀: τ = F_s/A₀, σ_n = F_n/A₀ (on the kinematic block τ = P₁₂,
σ_n = P₂₂ exactly). Measures G = slope of τ against γ_g over the modulus window (|γ_g| in it; with
R² and standard error like E), G from the plate travel beside it, and at the end the normal
stress σ_n and the normal-stress difference N₁ = σ₁₁ − σ₂₂ of the centre average.
"""

from __future__ import annotations

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import MIN_STRAIN, LoadFromZero, PlotSpec, TestKind, relative_error, strain_bound

SHEAR_LIMIT = 5.0  # largest |γ| a scene may ask for


class SimpleShear(LoadFromZero, TestKind):
    name = "simple-shear"
    load_key = "shear"
    rest = 0.0
    control_name = "shear"
    axes = (0,)
    oracle_setups = {"block": "kinematic"}
    cyclic = True
    effects = True
    symmetric = False  # shear is antisymmetric about the planes a reduction would cut
    force_column, control_column = "shear_force", "shear"
    measures_E = False
    plot = PlotSpec("shear_gauge", "shear_stress", "shear strain γ [–] (gauge marks)",
                    "nominal stress [MPa]",
                    (("shear_gauge", "shear_stress", "shear_stress"),
                     ("shear_gauge", "normal_stress", "normal_stress")), reference_x="shear")
    measured_units = {"G": "MPa", "G_plate": "MPa", "normal_stress_at_peak": "MPa",
                      "normal_stress_difference": "MPa"}
    doc = "simple shear x = X + γ Y e1 (kinematic block) or between rigid plates"
    gauge, readers = "shear-gauge", ("normal-force", "centre-cauchy")  # vlab/measure/kinds.py
    field_probe, fit = "simple-shear", "shear"
    units = {"shear": "1 (plate travel / gap)", "shear_gauge": "1 (gauge marks)", "shear_force": "N",
             "normal_force": "N (tension > 0)", "shear_stress": "MPa (F_s / plate area)",
             "normal_stress": "MPa (F_n / plate area)", "centre_cauchy": "MPa (FE centre average)", "time": "s"}

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        field, v = t.field("shear"), t.get("shear")
        if protocol == "cyclic":
            if not isinstance(v, list) or not 1 <= len(v) <= 50:
                raise SceneError(f"{field} must be a list of 1..50 rising shear amplitudes (> 0, <= "
                                 f"{SHEAR_LIMIT:g}) for test.protocol = 'cyclic', got {fields.show(v)}")
            amps = tuple(fields.number(f"{field}[{i}]", x, gt=0, le=SHEAR_LIMIT) for i, x in enumerate(v))
            if amps[0] < MIN_STRAIN:
                raise SceneError(f"{strain_bound(f'{field}[0]')}, got {amps[0]!r}")
            if any(b <= a for a, b in zip(amps, amps[1:])):
                raise SceneError(f"{field} must rise with every cycle, got {list(amps)}")
            return (amps[-1],)
        if isinstance(v, list):
            raise SceneError(f"{field} must be a single number (|γ| <= {SHEAR_LIMIT:g}, not 0) unless "
                             f"test.protocol = 'cyclic', got {fields.show(v)}")
        gamma = fields.number(field, v, ge=-SHEAR_LIMIT, le=SHEAR_LIMIT, note=" (amount of shear γ, not 0)")
        if gamma == 0.0:
            raise SceneError(f"{field} must not be 0 (no shear applies no load), allowed "
                             f"-{SHEAR_LIMIT:g}..{SHEAR_LIMIT:g}")
        if abs(gamma) < MIN_STRAIN:
            raise SceneError(f"{strain_bound(f'|{field}|')}, got {gamma!r}")
        return (gamma,)

    def amplitudes(self, t: fields.Table) -> tuple[float, ...]:
        """The cyclic amplitudes as given (parse_load has validated them)."""
        return tuple(float(x) for x in t.raw["shear"])

    def check(self, test, effects: dict) -> None:
        super().check(test, effects)
        if test.grips not in ("kinematic", "plates"):
            raise SceneError(f"test.grips must be 'kinematic' or 'plates' for test.kind = 'simple-shear', "
                             f"got {test.grips!r}")
        if test.protocol.name == "creep":  # its record and figure are an extensometer strain under a held pull
            raise SceneError("test.protocol = 'creep' is not available with test.kind = 'simple-shear' in this "
                             "build (a creep test holds a tensile force and records the extensometer strain); "
                             "a held shear is test.protocol = 'relaxation'")

    def describe(self, values) -> str:
        return f"shear {values[0]:.4g}"

    def loading(self, specimen, X, test):
        from vlab.loading.shear_grips import kinematic_shear, plate_shear

        make = kinematic_shear if test.grips == "kinematic" else plate_shear
        return make(specimen, X, test.targets[0])

    def isochoric(self, values):
        F = np.eye(3)
        F[0, 1] = values[0]  # I + γ e1⊗e2 is isochoric already
        return F

    def areas(self, specimen) -> dict[int, float]:
        return {0: specimen.area0[1]}  # the plate (face normal to y)

    def state(self, material, values):
        from vlab.materials.homogeneous import simple_shear

        return simple_shear(material, values[0])

    def reference(self, material, curve) -> dict:
        states = [self.state(material, g) for g in zip(curve.stretch[0])]
        sigma = [s.cauchy for s in states]
        out = {"shear_stress": [float(s.P[0, 1]) for s in states],
               "normal_stress": [float(s.P[1, 1]) for s in states],
               "cauchy_xx": [float(c[0, 0]) for c in sigma], "cauchy_yy": [float(c[1, 1]) for c in sigma],
               "cauchy_zz": [float(c[2, 2]) for c in sigma], "cauchy_xy": [float(c[0, 1]) for c in sigma],
               "normal_stress_difference": [float(c[0, 0] - c[1, 1]) for c in sigma]}
        tau = curve.column("stress", 0)
        scale = max(float(np.max(np.abs(out["shear_stress"]), initial=0.0)), 1e-300)
        normal = np.asarray(curve.extra.get("normal_force", []), float) / curve.area0[0]
        out["max_relative_error_shear"] = relative_error(tau, out["shear_stress"])
        out["max_error_normal_over_shear"] = (float(np.max(np.abs(normal - out["normal_stress"][:len(normal)])))
                                              / scale if len(normal) else None)
        return out

    def columns(self, curve) -> dict[str, list[float]]:
        area = curve.area0[0]
        normal = list(curve.extra.get("normal_force", []))
        cols = {"shear": list(curve.stretch[0]), "shear_gauge": list(curve.strain[0]),
                "shear_force": list(curve.force[0]), "shear_stress": list(curve.column("stress", 0)),
                "normal_force": normal, "normal_stress": [f / area for f in normal]}
        return cols | {k: list(v) for k, v in curve.extra.items() if k.startswith("centre_cauchy")}


SIMPLE_SHEAR = SimpleShear()
