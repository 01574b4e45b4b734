"""``[effects.viscoelastic]``: Prony series on the isochoric part (vlab.materials.viscoelastic).

    [effects.viscoelastic]
    tau  = [1.0, 10.0]     # relaxation times τ_i, s (> 0)
    beta = [0.5, 0.3]      # relative moduli β_i ≥ 0: instantaneous shear modulus μ (1 + Σβ_i)

Ground laws: every model of the registry with an isochoric part (``isochoric``: Neo-Hookean and
the rubber models). The Maxwell branches are isochoric Neo-Hookean branches of shear modulus
β_i μ with μ the ground law's initial shear modulus μ0 (``elastic.mu``), so at small strain the
instantaneous shear modulus is μ0 (1 + Σβ_i) for every ground law; at finite strain the
branches stay Neo-Hookean whatever the ground law (vlab.materials.viscoelastic).

A rate-dependent effect: the scene must give time (test.strain_rate or test.ramp_time). Any
protocol is accepted (a monotonic test at a rate shows the rate-dependent stiffness). All β = 0
is inert: the run integrates the history at its cost and results.json says so in ``warnings``.
"""

from __future__ import annotations

from dataclasses import dataclass

from vlab.effects.registry import Effect
from vlab.loading.kinds import peak_grip_strain
from vlab.materials.registry import models_where
from vlab.fields import SceneError, number, show
from vlab.materials.viscoelastic import PronyViscoelastic

MAX_TERMS = 20


@dataclass(frozen=True)
class ViscoelasticSpec:
    tau: tuple[float, ...]  # s
    beta: tuple[float, ...]  # 1
    name: str = "viscoelastic"


def _series(t, key: str, n: int | None, **bounds) -> tuple[float, ...]:
    v = t.get(key)
    what = f"{n}" if n is not None else f"1..{MAX_TERMS}"
    if not isinstance(v, list) or not 1 <= len(v) <= MAX_TERMS or (n is not None and len(v) != n):
        raise SceneError(f"{t.field(key)} must be a list of {what} numbers (one per Prony term), got {show(v)}")
    return tuple(number(f"{t.field(key)}[{i}]", x, **bounds) for i, x in enumerate(v))


def parse(t, material, test) -> ViscoelasticSpec:
    tau = _series(t, "tau", None, gt=0, le=1e9)
    return ViscoelasticSpec(tau=tau, beta=_series(t, "beta", len(tau), ge=0, le=1e4))


def build(spec: ViscoelasticSpec, elastic) -> PronyViscoelastic:
    return PronyViscoelastic(elastic, tau=spec.tau, beta=spec.beta)


def warnings(spec: ViscoelasticSpec, material, test) -> list[str]:
    found = []
    if not any(spec.beta):
        found.append("effects.viscoelastic: every beta is 0, so the material is elastic; the history "
                     "is still integrated (at its cost) and the result equals the elastic run")
    p = test.protocol
    if p.timed and p.name != "creep":
        span = peak_grip_strain(test)
        ramp = p.ramp_time if p.ramp_time is not None else span / p.strain_rate
        if ramp > 50 * max(spec.tau) and not p.has_hold:
            found.append(f"effects.viscoelastic: the ramp ({ramp:g} s) is > 50 times the longest "
                         f"relaxation time ({max(spec.tau):g} s): the test is practically at equilibrium "
                         "and shows little rate dependence")
    return found


EFFECT = Effect(name="viscoelastic", keys=("tau", "beta"), parse=parse, role="material", build=build,
                timed=True, models=models_where(lambda m: m.isochoric), warnings=warnings,
                doc="finite-strain Prony-series viscoelasticity on the isochoric part")
