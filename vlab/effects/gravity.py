"""``[effects.gravity]``: the specimen's self-weight as a constant body force.

    [material]
    density = 1100          # kg/m³ (converted to t/mm³, the mass unit of N, mm, s)
    [effects.gravity]
    g = 9.81                # m/s², default 9.81 (converted to mm/s²)
    direction = "-x"        # default: down the test axis

The body force per reference volume is b = ρ g e (N/mm³), e the unit vector of ``direction``.
Default "-x": the loading axis vertical, the fixed grip at the bottom and the moving crosshead
(with the load cell) above it, as on an ordinary vertical tensile machine; the load cell then
reads the weight the upper grip carries (labs tare it; vlab does not). Gravity enters the total
energy as −f_extᵀu with f_ext = ∫ ρ g e · N dV (vlab.fe.external_load) and is applied in full
before the grips move, so the first recorded state is the specimen settled under its weight.
"""

from __future__ import annotations

from dataclasses import dataclass

from vlab.effects.registry import Effect
from vlab.fields import SceneError

DIRECTIONS = ("-x", "+x", "-y", "+y", "-z", "+z")
M_PER_S2 = 1e3  # mm/s² per m/s²


@dataclass(frozen=True)
class GravitySpec:
    g: float  # mm/s²
    direction: tuple[float, float, float]  # unit vector
    name: str = "gravity"


def parse(t, material, test) -> GravitySpec:
    if material.density is None:
        raise SceneError("effects.gravity needs material.density (kg/m³, > 0)")
    g = t.number("g", default=9.81, gt=0, le=1000, note=" m/s²")
    word = t.choice("direction", DIRECTIONS, default="-x")
    axis = "xyz".index(word[1])
    e = [0.0, 0.0, 0.0]
    e[axis] = -1.0 if word[0] == "-" else 1.0
    return GravitySpec(g=g * M_PER_S2, direction=tuple(e))  # type: ignore[arg-type]


def build(spec: GravitySpec, scene, space):
    from vlab.fe.external_load import body_force_vector
    b = [scene.material.density * spec.g * c for c in spec.direction]
    return body_force_vector(space, b)


EFFECT = Effect(name="gravity", keys=("g", "direction"), parse=parse, role="load", build=build,
                doc="self-weight of the specimen (density from [material])")
