"""Biaxial tension or compression: ``stretch = [λx, λy]`` (two numbers, 0.2..10; any ratio,
equibiaxial included).

Grips move along x and y; on the roller block (or a sheet) the oracle is F = diag(λx, λy, t) with
P₃₃ = 0 (materials.homogeneous.biaxial; plane strain diag(λx, λy, 1)). Measures E and ν from the
plane-stress relations s_a = E/(1−ν²)(ε_a + ν ε_b) and ε_t = −ν/(1−ν)(ε_x + ε_y), or, on a
cruciform, from the FE centre averages (measure/elastic_constants.py).
"""

from __future__ import annotations

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import PlotSpec, TestKind, stretch_value


class Biaxial(TestKind):
    name = "biaxial"
    axes = (0, 1)
    oracle_setups = {"block": "roller", "sheet": "roller"}
    effects = True
    lateral_ratio = True
    plot = PlotSpec("strain", "stress", "engineering strain [–] (extensometer)", "engineering stress [MPa]",
                    (("strain", "stress", "stress_x"), ("strain_y", "stress_y", "stress_y")))
    doc = "biaxial tension or compression along x and y, any ratio"
    fit = "biaxial"  # E and ν from both axes (vlab/measure/kinds.py)

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        v = t.get("stretch")
        if not isinstance(v, list) or len(v) != 2:
            raise SceneError(f"{t.field('stretch')} must be a list [sx, sy] of 2 numbers for kind = 'biaxial' "
                             f"(each 0.2..10), got {fields.show(v)}")
        return tuple(stretch_value(f"{t.field('stretch')}[{i}]", x) for i, x in enumerate(v))

    def state(self, material, values):
        from vlab.materials.homogeneous import homogeneous_biaxial

        return homogeneous_biaxial(material, *values)

    def isochoric(self, values):
        import numpy as np

        return np.diag([values[0], values[1], 1.0 / (values[0] * values[1])])  # diag(λx, λy, 1/(λx λy))


BIAXIAL = Biaxial()
