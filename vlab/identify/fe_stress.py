"""The constants of a scene's material, flat, and ∂P/∂p of its stress field for every one of them.

Flat names: a card's scalars by their keys (C10, Jm, lambda_m, ...), a series model's lists one
entry each (Ogden: mu[0], mu[1], alpha[0], ...), and K, the bulk modulus (MPa; vlab's
Neo-Hookean: mu and K of its moduli). ``card_table`` puts them back into [material] keys.

Every model of the library is isotropic, so at a deformation F = Σ_A λ_A n_A ⊗ N_A
    P = Σ_A (τ_A/λ_A) n_A ⊗ N_A,
with τ_A the principal Kirchhoff stresses (MPa), functions of λ and of the constants p only (the
frame n, N is F's). Hence, at fixed F,
    ∂P/∂p = Σ_A (∂τ_A/∂p / λ_A) n_A ⊗ N_A,
and ∂τ_A/∂p comes from the identification library's τ (vlab.identify.states.principal_tau: the
isochoric w̄_A of vlab.identify.laws at λ̄ = J^(−1/3) λ, deviatoric part, plus J U'(J); vlab's
Neo-Hookean μ(λ_A² − 1) + (K − 2μ/3) ln J) by the complex step,
    ∂τ/∂p = Im τ(p + i h) / h,   h = 1e-30 max(|p|, 1),
exact to round-off for every model (Ogden's μp and αp, Gent's Jm, Arruda–Boyce's λm, K alike:
no truncation error, no cancellation). The same τ equals the FE library's stress
(tests/test_fit_fe_stress.py checks P to 1e-12 and ∂P/∂p against central differences of the
FE library's stress). The sum over A is insensitive to coalescent stretches (equal λ_A give
equal τ_A and ∂τ_A/∂p, so any orthonormal frame of the eigenspace gives the same tensor).
"""

from __future__ import annotations

import re

import numpy as np

from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, principal_tau

__all__ = ["flat_constants", "card_table", "stress_derivatives", "principal_stress_of"]

_ENTRY = re.compile(r"^([A-Za-z_]+)\[(\d+)\]$")
STEP = 1e-30


def flat_constants(material) -> dict[str, float]:
    """{flat name: value} of a parsed [material] (vlab.materials.card.MaterialSpec), K included."""
    m = material.moduli
    out = {"mu": float(m.mu)} if material.model == "neo-hookean" else {}
    for key, v in (getattr(material, "params", None) or {}).items():
        if isinstance(v, (list, tuple)):
            out |= {f"{key}[{i}]": float(x) for i, x in enumerate(v)}
        else:
            out[key] = float(v)
    return out | {"K": float(m.lmbda + 2.0 * m.mu / 3.0)}


def card_table(values: dict[str, float]) -> dict:
    """Flat constants back to [material] keys: "mu[0]", "mu[1]" → mu = [..]."""
    out: dict = {}
    lists: dict[str, dict[int, float]] = {}
    for name, v in values.items():
        m = _ENTRY.match(name)
        if m:
            lists.setdefault(m.group(1), {})[int(m.group(2))] = float(v)
        else:
            out[name] = float(v)
    return out | {k: [d[i] for i in sorted(d)] for k, d in lists.items()}


def _constitutive(model: str, values: dict, volumetric: str | None) -> Constitutive:
    terms = sum(1 for n in values if n.startswith("alpha[")) or 1
    return Constitutive(law_for(model, terms), "fixed", float(values["K"]), volumetric or "quadratic")


def _tau(law: Constitutive, values: dict, lam: np.ndarray):
    c = [values[n] for n in law.law.names]
    return np.array(principal_tau(law, c, values["K"], lam[0], lam[1], lam[2]))


def stress_derivatives(F: np.ndarray, model: str, values: dict, names, volumetric: str | None = None) -> dict:
    """{p: ∂P/∂p (3, 3, *batch)} at deformations F (3, 3, *batch), MPa per unit of p."""
    from vlab.materials.principal import principal_frame, principal_stress

    frame = principal_frame(F)
    law = _constitutive(model, values, volumetric)
    out = {}
    for p in names:
        h = STEP * max(abs(values[p]), 1.0)
        dtau = np.imag(_tau(law, values | {p: values[p] + 1j * h}, frame.lam)) / h
        out[p] = principal_stress(frame, dtau)
    return out


def principal_stress_of(F: np.ndarray, model: str, values: dict, volumetric: str | None = None) -> np.ndarray:
    """P (3, 3, *batch) of the identification library's τ at F: the check against the FE library."""
    from vlab.materials.principal import principal_frame, principal_stress

    frame = principal_frame(F)
    return principal_stress(frame, _tau(_constitutive(model, values, volumetric), values, frame.lam))
