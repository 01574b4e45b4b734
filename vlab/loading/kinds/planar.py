"""Planar tension (pure shear): ``stretch = λ`` (one number, 0.2..10).

The lateral stretch is held at 1 and the thickness is free, F = diag(λ, 1, t) with P₃₃ = 0
(materials.homogeneous.planar). On the roller block the x grips move and the y grips hold
(u_y = 0 on both y faces, free to slide along x and z), which is exactly that state (the oracle).
The planar-tension specimen (geometry/planar.py: a wide short strip, width/height ≥ 10, clamped
along its long edges) approaches it at its centre; its distance from pure shear is reported.

Measures the planar modulus E_p = E/(1 − ν²) (slope of the nominal stress F/A₀ against the
extensometer strain over the modulus window: with ε_y = 0 and σ_z = 0 Hooke's law gives
σ_y = ν σ_x on the lateral grips and σ_x = E/(1 − ν²) ε_x), ν from the thickness strain
ε_z = −ν/(1 − ν) ε_x (ν = r/(1 + r), r = −dε_z/dε_x), E = (1 − ν²) E_p; and the nominal
stress–stretch curve (measure/planar.py). The transverse strain is held (≈ 0): no apparent
Poisson's ratio.
"""

from __future__ import annotations

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import PlotSpec, TestKind, stretch_value


class Planar(TestKind):
    name = "planar"
    axes = (0,)
    oracle_setups = {"block": "roller", "sheet": "roller"}
    cyclic = True  # stretch-driven cycles, as uniaxial (Mullins softening in pure shear)
    effects = True
    force_column, control_column = "force", "stretch"
    measures_E = True
    plot = PlotSpec("stretch", "stress", "grip stretch λ [–]", "nominal stress F/A₀ [MPa]",
                    (("stretch", "stress", "stress_x"),))
    measured_units = {"planar_modulus": "MPa", "thickness_strain_ratio": "1"}
    doc = "planar tension (pure shear): lateral stretch held at 1, thickness free"
    fit, field_probe = "planar", "pure-shear"  # vlab/measure/kinds.py

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        v = t.get("stretch")
        if isinstance(v, list):
            raise SceneError(f"{t.field('stretch')} must be a single number for kind = 'planar' (the lateral "
                             f"stretch is held at 1), got {fields.show(v)}")
        return (stretch_value(t.field("stretch"), v),)

    def grip_stretches(self, targets: tuple[float, ...]) -> tuple[float, ...]:
        return (targets[0], 1.0)  # the y grips hold the lateral stretch at 1

    def loading(self, specimen, X, test):
        from vlab.loading.grips import grip_loading

        # a planar-tension specimen's clamps along its long edges hold the width themselves
        held = self.grip_stretches(test.targets) if test.grips == "roller" else test.targets
        return grip_loading(specimen, X, held, test.grips)

    def state(self, material, values):
        from vlab.materials.homogeneous import planar

        return planar(material, values[0])

    def isochoric(self, values):
        import numpy as np

        return np.diag([values[0], 1.0, 1.0 / values[0]])  # diag(λ, 1, 1/λ)

    def columns(self, curve) -> dict[str, list[float]]:
        return super().columns(curve) | {"crosshead_strain": curve.crosshead_strain(0).tolist()}


PLANAR = Planar()
