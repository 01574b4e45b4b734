"""St. Venant–Kirchhoff: Hooke's law in the Green strain (objective, but soft in compression)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.base import Material
from vlab.materials.structure import TangentTerms
from vlab.tensor import as_tensor_field, dot, green_strain, trace, transpose

__all__ = ["StVenantKirchhoff"]


@dataclass(frozen=True)
class StVenantKirchhoff(Material):
    """St. Venant–Kirchhoff model.

    With C = FᵀF, E = ½(C − I) (Green strain), shapes (3,3,*batch):

    - ψ = ½λ (tr E)² + μ tr(E²)                                   shape (*batch), MPa
    - S = λ tr(E) I + 2μ E  (second Piola–Kirchhoff),  P = F S    shape (3,3,*batch), MPa
    - A_iJkL = δ_ik S_JL + F_iM ℂ_MJNL F_kN  with ℂ = λ I⊗I + μ(δ_MN δ_JL + δ_ML δ_JN), i.e.
      A_iJkL = δ_ik S_JL + λ F_iJ F_kL + μ (FFᵀ)_ik δ_JL + μ F_iL F_kJ
                                                                 shape (3,3,3,3,*batch), MPa

    ψ is quartic in F and finite everywhere; under strong compression it softens and an
    inverted element can stay inverted (e.g. ψ(−I) = ψ(I) = 0).
    """

    name: ClassVar[str] = "stvk"
    is_linear: ClassVar[bool] = False

    def _pk2(self, E: np.ndarray) -> np.ndarray:
        ltr = self.lmbda * trace(E)
        S = 2.0 * self.mu * E
        for i in range(3):
            S[i, i] += ltr
        return S

    def energy(self, F) -> np.ndarray:
        """ψ = ½λ(tr E)² + μ E:E, shape (*batch), MPa."""
        E = green_strain(as_tensor_field(F))
        tr = trace(E)
        return 0.5 * self.lmbda * tr * tr + self.mu * np.einsum("ij...,ij...->...", E, E)

    def stress(self, F) -> np.ndarray:
        """P = F S, S = λ tr(E) I + 2μE, shape (3,3,*batch), MPa."""
        F = as_tensor_field(F)
        return dot(F, self._pk2(green_strain(F)))

    def tangent(self, F) -> np.ndarray:
        """A_iJkL = δ_ik S_JL + λ F_iJ F_kL + μ b_ik δ_JL + μ F_iL F_kJ (b = FFᵀ), MPa."""
        return self.tangent_terms(F).full()

    def tangent_terms(self, F) -> TangentTerms:
        """kron (δ, S) + kron (μb, δ) + dyad (λF, F) + cross (μF, F)."""
        F = as_tensor_field(F)
        S = self._pk2(green_strain(F))
        b = dot(F, transpose(F))
        b *= self.mu
        return TangentTerms(F.shape[2:], kron=[(1.0, S), (b, 1.0)], dyad=[((self.lmbda, F), F)],
                            cross=[((self.mu, F), F)])
