"""``[effects.mullins]``: Ogden–Roxburgh stress softening over the ground law (vlab.materials.mullins).

    [effects.mullins]
    r = 2.0        # > 1: the largest softening is 1/r
    m = 0.5        # > 0, MPa: energy scale of the softening
    beta = 0.0     # ≥ 0: growth of m with the largest past energy, default 0

The ground law ψ₀ is the scene's ``material.model``; the state is W_max, the largest ψ₀ reached.
Below W_max the stress is η P₀ with η = 1 − erf((W_max − ψ₀)/(m + βW_max))/r. Only unloading
and reloading show the effect, so the protocol must be load-unload or cyclic (a monotonic test
follows the primary curve, the ground law, exactly: a SceneError says so). History output per
cell: ``max_energy`` W_max (MPa) and ``softening`` η (1 on the primary curve).
"""

from __future__ import annotations

from dataclasses import dataclass

from vlab.effects.registry import Effect
from vlab.materials.base import Material
from vlab.fields import SceneError, Table
from vlab.materials.mullins import OgdenRoxburgh


PARAM_KEYS = ("r", "m", "beta")


def parse_params(raw: dict, prefix: str, elastic: Material) -> OgdenRoxburgh:
    """Build the law from ``[effects.mullins]`` over the ground law ``elastic``.

    Keys: r > 1 (required; the largest softening is 1/r), m > 0 MPa (required; energy scale),
    beta ≥ 0 (default 0; growth of the scale with W_max).
    """
    t = Table(prefix, raw, PARAM_KEYS)
    r = t.number("r", gt=1.0, note=" (dimensionless; the largest softening is 1/r)")
    m = t.number("m", gt=0.0, note=" (MPa, energy scale of the softening)")
    beta = t.number("beta", 0.0, ge=0.0, note=" (dimensionless; growth of m with the maximum energy)")
    return OgdenRoxburgh(elastic, r=r, m=m, beta=beta)


@dataclass(frozen=True)
class MullinsSpec:
    r: float  # 1
    m: float  # MPa
    beta: float  # 1
    name: str = "mullins"


def parse(t, material, test) -> MullinsSpec:
    if not test.protocol.unloads:
        raise SceneError(f"effects.mullins cannot show with test.protocol = {test.protocol.name!r}: the "
                         "Mullins effect is a softening on unloading and reloading below the largest past "
                         "strain, and a test that never unloads follows the ground law exactly; use "
                         "test.protocol = 'load-unload' or 'cyclic' (rising test.amplitudes)")
    try:
        law = parse_params(t.raw, "effects.mullins", material.moduli)
    except ValueError as exc:
        raise SceneError(str(exc)) from None
    return MullinsSpec(law.r, law.m, law.beta)


def build(spec: MullinsSpec, elastic) -> OgdenRoxburgh:
    return OgdenRoxburgh(elastic, r=spec.r, m=spec.m, beta=spec.beta)


EFFECT = Effect(name="mullins", keys=PARAM_KEYS, parse=parse, role="material", build=build,
                protocols=("load-unload", "cyclic"),
                doc="Ogden–Roxburgh stress softening with memory of the largest past deformation")
