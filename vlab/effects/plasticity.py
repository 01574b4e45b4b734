"""``[effects.plasticity]``: finite-strain J2 plasticity with isotropic hardening (vlab.materials.plasticity).

    [effects.plasticity]
    yield_stress = 20.0          # σ_y0 > 0, MPa (initial yield stress, Kirchhoff/von Mises)
    hardening_modulus = 100.0    # H ≥ 0, MPa (linear hardening), default 0
    saturation_stress = 0.0      # Q ≥ 0, MPa (Voce saturation), default 0
    saturation_exponent = 0.0    # δ > 0 when Q > 0

Flow stress σ_y(α) = σ_y0 + Hα + Q(1 − e^(−δα)), α the accumulated plastic strain. The elastic
part is Hencky with the scene's Lamé constants (E, ν): equal to every ground law at small
strain, so E and ν are measured as without the effect; at finite elastic strain it is Hencky,
whatever ``material.model`` says (a warning in results.json says so). Rate-independent.
Protocols: monotonic (a plain tensile test of a plastic material), load-unload and cyclic,
where the permanent set shows. History output: ``plastic_strain`` α per cell.
"""

from __future__ import annotations

from dataclasses import dataclass

from vlab.effects.registry import Effect
from vlab.loading.kinds import peak_grip_strain
from vlab.materials.base import Material
from vlab.materials.registry import models_where
from vlab.fields import SceneError, Table
from vlab.materials.hencky import Hencky
from vlab.materials.plasticity import J2Plasticity


PARAM_KEYS = ("yield_stress", "hardening_modulus", "saturation_stress", "saturation_exponent")


def parse_params(raw: dict, prefix: str, elastic: Material) -> J2Plasticity:
    """Build the law from ``[effects.plasticity]``; the elastic part is Hencky with the Lamé
    constants of ``elastic`` (the scene's ground law).

    Keys: yield_stress σ_y0 > 0 MPa (required), hardening_modulus H ≥ 0 MPa (default 0),
    saturation_stress Q ≥ 0 MPa (default 0), saturation_exponent δ > 0 (required when Q > 0).
    """
    t = Table(prefix, raw, PARAM_KEYS)
    sy = t.number("yield_stress", gt=0.0, note=" (MPa, initial yield stress)")
    H = t.number("hardening_modulus", 0.0, ge=0.0, note=" (MPa, linear hardening modulus)")
    Q = t.number("saturation_stress", 0.0, ge=0.0, note=" (MPa, Voce saturation increase of the yield stress)")
    if Q > 0.0:
        d = t.number("saturation_exponent", gt=0.0, note=" (Voce exponent, required when saturation_stress > 0)")
    else:
        d = t.number("saturation_exponent", 0.0, ge=0.0, note=" (Voce exponent)")
    return J2Plasticity(Hencky(elastic.lmbda, elastic.mu), yield_stress=sy, hardening_modulus=H,
                        saturation_stress=Q, saturation_exponent=d)


@dataclass(frozen=True)
class PlasticitySpec:
    yield_stress: float  # MPa
    hardening_modulus: float  # MPa
    saturation_stress: float  # MPa
    saturation_exponent: float  # 1
    name: str = "plasticity"


def parse(t, material, test) -> PlasticitySpec:
    try:
        law = parse_params(t.raw, "effects.plasticity", material.moduli)
    except ValueError as exc:
        raise SceneError(str(exc)) from None
    return PlasticitySpec(law.yield_stress, law.hardening_modulus, law.saturation_stress,
                          law.saturation_exponent)


def build(spec: PlasticitySpec, elastic) -> J2Plasticity:
    return J2Plasticity(Hencky(elastic.lmbda, elastic.mu), yield_stress=spec.yield_stress,
                        hardening_modulus=spec.hardening_modulus, saturation_stress=spec.saturation_stress,
                        saturation_exponent=spec.saturation_exponent)


def warnings(spec: PlasticitySpec, material, test) -> list[str]:
    found = [f"effects.plasticity: the elastic part is Hencky with material E = {material.moduli.E:g} MPa, "
             f"nu = {material.moduli.nu:g} (the same at small strain; material.model = "
             f"{material.model!r} is not used at finite elastic strain)"]
    E, G = material.moduli.E, material.moduli.mu
    peak = peak_grip_strain(test)
    if test.kind == "simple-shear":  # von Mises in shear: τ_y = σ_y0/√3 at γ_y = τ_y/G
        if peak < spec.yield_stress / (3.0**0.5 * G):
            found.append(f"effects.plasticity: the largest amount of shear {peak:g} is below the yield "
                         f"shear strain σ_y0/(√3 G) = {spec.yield_stress / (3.0**0.5 * G):g}: the specimen "
                         "may stay elastic")
    elif peak < spec.yield_stress / E:
        found.append(f"effects.plasticity: the largest grip strain {peak:g} is below the uniaxial yield "
                     f"strain σ_y0/E = {spec.yield_stress / E:g}: the specimen may stay elastic")
    return found


EFFECT = Effect(name="plasticity", keys=PARAM_KEYS, parse=parse, role="material", build=build,
                protocols=("monotonic", "load-unload", "cyclic"), warnings=warnings,
                models=models_where(lambda m: m.hencky),  # Hencky with the card's E, ν is their small-strain law
                doc="finite-strain J2 plasticity with isotropic hardening (permanent set)")
