"""St. Venant–Kirchhoff with the volumetric part replaced by a penalty on (J − 1)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.base import Material
from vlab.tensor import as_tensor_field, cofactor, det, dot, dyad, dyad_il, green_strain, transpose

__all__ = ["StVKVolumetric"]

# Nonzero entries of D_iJkL = ε_ikm ε_JLN F_mN = ∂(cof F)_iJ/∂F_kL: i≠k and J≠L; m, N are the
# remaining indices and the sign is ε_ikm ε_JLN. 36 entries (i, J, k, L, m, N, sign > 0).
_PAIRS = [(i, k, 3 - i - k, (k - i) % 3 == 1) for i in range(3) for k in range(3) if i != k]
_D_ENTRIES = tuple(
    (i, J, k, L, m, N, si == sJ) for (i, k, m, si) in _PAIRS for (J, L, N, sJ) in _PAIRS
)


@dataclass(frozen=True)
class StVKVolumetric(Material):
    """StVK with a (J − 1)² volume term (resists collapse/inversion, unlike plain StVK).

    With J = det F, E = ½(FᵀF − I), cof F = J F⁻ᵀ, b = FFᵀ, and η = λ/2 (chosen so that the
    linearisation at F = I is λ I⊗I + μ(δδ + δδ), the same λ, μ as every other model):

    - ψ = η (J − 1)² + μ tr(E²)                                    shape (*batch), MPa
    - P = 2η (J − 1) J F⁻ᵀ + 2μ F E                               shape (3,3,*batch), MPa
    - A_iJkL = 2η [ cof_iJ cof_kL + (J − 1) ε_ikm ε_JLN F_mN ]
               + 2μ δ_ik E_JL + μ b_ik δ_JL + μ F_iL F_kJ          shape (3,3,3,3,*batch), MPa

      using ∂(cof F)_iJ/∂F_kL = ε_ikm ε_JLN F_mN = J(F⁻ᵀ_iJ F⁻ᵀ_kL − F⁻ᵀ_iL F⁻ᵀ_kJ), so
      A_vol = 2η J[(2J − 1) F⁻ᵀ_iJ F⁻ᵀ_kL − (J − 1) F⁻ᵀ_iL F⁻ᵀ_kJ]. The ε-form used here
      needs no inverse and is finite for every F (also J ≤ 0).

    ψ is finite for every F (inverted states cost energy η(J − 1)² but are not excluded).
    """

    name: ClassVar[str] = "stvk-volumetric"
    is_linear: ClassVar[bool] = False

    @property
    def eta(self) -> float:
        """Volume-penalty coefficient η = λ/2, MPa."""
        return 0.5 * self.lmbda

    def energy(self, F) -> np.ndarray:
        """ψ = η(J − 1)² + μ E:E, shape (*batch), MPa."""
        F = as_tensor_field(F)
        E = green_strain(F)
        Jm1 = det(F) - 1.0
        return self.eta * Jm1 * Jm1 + self.mu * np.einsum("ij...,ij...->...", E, E)

    def stress(self, F) -> np.ndarray:
        """P = 2η(J − 1) cof F + 2μ F E, shape (3,3,*batch), MPa."""
        F = as_tensor_field(F)
        cof = cofactor(F)
        J = det(F, cof)
        P = dot(F, green_strain(F))
        P *= 2.0 * self.mu
        P += (2.0 * self.eta) * (J - 1.0) * cof
        return P

    def tangent(self, F) -> np.ndarray:
        """A = 2η[cof⊗cof + (J − 1) ∂cof/∂F] + 2μ I⊗̄E + μ b_ik δ_JL + μ F_iL F_kJ, MPa."""
        F = as_tensor_field(F)
        cof = cofactor(F)
        J = det(F, cof)
        two_eta = 2.0 * self.eta
        A = dyad(two_eta * cof, cof)                      # 2η cof_iJ cof_kL
        cF = (two_eta * (J - 1.0)) * F                    # 2η(J − 1) ε_ikm ε_JLN F_mN
        for i, J_, k, L, m, N, positive in _D_ENTRIES:
            if positive:
                A[i, J_, k, L] += cF[m, N]
            else:
                A[i, J_, k, L] -= cF[m, N]
        dyad_il(self.mu * F, transpose(F), out=A)         # μ F_iL F_kJ
        twomuE = green_strain(F)
        twomuE *= 2.0 * self.mu
        b = dot(F, transpose(F))
        b *= self.mu
        for i in range(3):
            A[i, :, i, :] += twomuE                       # 2μ δ_ik E_JL
            A[:, i, :, i] += b                            # μ b_ik δ_JL
        return A
