"""Common base for the hyperelastic material models.

Every model is a frozen dataclass with the Lamé constants ``lmbda`` and ``mu`` (MPa) and three
pure-numpy methods, vectorised over any trailing batch shape:

- ``energy(F)  -> psi``  shape ``(*batch)``, MPa (= mJ/mm³), strain energy per reference volume
- ``stress(F)  -> P``    shape ``(3, 3, *batch)``, MPa, first Piola–Kirchhoff, P_iJ = ∂ψ/∂F_iJ
- ``tangent(F) -> A``    shape ``(3, 3, 3, 3, *batch)``, MPa, A_iJkL = ∂P_iJ/∂F_kL

``F`` (the deformation gradient) has shape ``(3, 3, *batch)``: tensor indices LEAD, batch axes
TRAIL. Class attributes: ``name`` (registry key) and ``is_linear`` (True only when ψ is
quadratic in the displacement gradient, so one Newton step is exact).

All models linearise at F = I to the same isotropic small-strain law
A(I) = λ I⊗I + μ(δ_ik δ_JL + δ_iL δ_Jk), so at small strain every model returns
E = μ(3λ + 2μ)/(λ + μ) and ν = λ/(2(λ + μ)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.capabilities import LawCapabilities

__all__ = ["Material"]


@dataclass(frozen=True)
class Material(LawCapabilities):
    """Abstract isotropic hyperelastic material with Lamé constants ``lmbda``, ``mu`` (MPa).

    Raises ValueError unless both are finite, μ > 0 and the bulk modulus K = λ + 2μ/3 > 0
    (i.e. E > 0 and −1 < ν < ½).
    """

    lmbda: float
    mu: float

    name: ClassVar[str] = "abstract"
    is_linear: ClassVar[bool] = False

    def __post_init__(self) -> None:
        lm, mu = float(self.lmbda), float(self.mu)
        if not (math.isfinite(lm) and math.isfinite(mu)):
            raise ValueError(f"{self.name}: Lamé constants must be finite, got lmbda={lm}, mu={mu}")
        if mu <= 0.0:
            raise ValueError(f"{self.name}: shear modulus mu must be > 0, got {mu}")
        if lm + 2.0 * mu / 3.0 <= 0.0:
            raise ValueError(
                f"{self.name}: bulk modulus lmbda + 2 mu/3 must be > 0 (nu > -1), got lmbda={lm}, mu={mu}"
            )
        object.__setattr__(self, "lmbda", lm)
        object.__setattr__(self, "mu", mu)

    # --- small-strain constants (identical for every model) -------------------------------
    @property
    def youngs_modulus(self) -> float:
        """Small-strain Young's modulus E = μ(3λ + 2μ)/(λ + μ), MPa."""
        return self.mu * (3.0 * self.lmbda + 2.0 * self.mu) / (self.lmbda + self.mu)

    @property
    def poisson_ratio(self) -> float:
        """Small-strain Poisson's ratio ν = λ/(2(λ + μ)), dimensionless."""
        return self.lmbda / (2.0 * (self.lmbda + self.mu))

    @property
    def bulk_modulus(self) -> float:
        """Small-strain bulk modulus K = λ + 2μ/3, MPa."""
        return self.lmbda + 2.0 * self.mu / 3.0

    # --- the model ---------------------------------------------------------------------------
    def energy(self, F) -> np.ndarray:  # pragma: no cover - abstract
        """Strain energy density ψ(F), shape (*batch), MPa."""
        raise NotImplementedError

    def stress(self, F) -> np.ndarray:  # pragma: no cover - abstract
        """First Piola–Kirchhoff stress P = ∂ψ/∂F, shape (3,3,*batch), MPa."""
        raise NotImplementedError

    def tangent(self, F) -> np.ndarray:  # pragma: no cover - abstract
        """Tangent A = ∂P/∂F, shape (3,3,3,3,*batch), MPa."""
        raise NotImplementedError
