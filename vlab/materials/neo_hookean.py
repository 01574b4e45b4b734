"""Compressible Neo-Hookean model (ψ → ∞ as J → 0⁺; inverted states are inadmissible)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.base import Material
from vlab.materials.structure import TangentTerms
from vlab.tensor import as_tensor_field, det, inv_transpose

__all__ = ["NeoHookean"]


@dataclass(frozen=True)
class NeoHookean(Material):
    """Compressible Neo-Hookean model.

    With J = det F, C = FᵀF, F⁻ᵀ the inverse transpose (all (3,3,*batch) or (*batch)):

    - ψ = ½μ (tr C − 3) − μ ln J + ½λ (ln J)²                      shape (*batch), MPa
      ψ = +inf where J ≤ 0 (no warning).
    - P = μ (F − F⁻ᵀ) + λ ln(J) F⁻ᵀ                                 shape (3,3,*batch), MPa
    - A_iJkL = μ δ_ik δ_JL + (μ − λ ln J) F⁻ᵀ_iL F⁻ᵀ_kJ + λ F⁻ᵀ_iJ F⁻ᵀ_kL
      (F⁻ᵀ_iL F⁻ᵀ_kJ = F⁻¹_Li F⁻¹_Jk)                              shape (3,3,3,3,*batch), MPa

    stress/tangent where J ≤ 0 return nan/inf entries silently (no numpy warnings); the solver
    must never accept such a state.
    """

    name: ClassVar[str] = "neo-hookean"
    is_linear: ClassVar[bool] = False

    def energy(self, F) -> np.ndarray:
        """ψ = ½μ(tr C − 3) − μ ln J + ½λ(ln J)², +inf where J ≤ 0; shape (*batch), MPa."""
        F = as_tensor_field(F)
        J = det(F)
        ok = J > 0.0
        lnJ = np.log(np.where(ok, J, 1.0))
        trC = np.einsum("ij...,ij...->...", F, F)
        psi = 0.5 * self.mu * (trC - 3.0) - self.mu * lnJ + 0.5 * self.lmbda * lnJ * lnJ
        return np.where(ok, psi, np.inf)

    def stress(self, F) -> np.ndarray:
        """P = μ(F − F⁻ᵀ) + λ ln(J) F⁻ᵀ, shape (3,3,*batch), MPa."""
        F = as_tensor_field(F)
        with np.errstate(all="ignore"):
            G, J = inv_transpose(F)
            G *= self.lmbda * np.log(J) - self.mu
            G += self.mu * F
        return G

    def tangent(self, F) -> np.ndarray:
        """A = μ δ_ik δ_JL + (μ − λ ln J) F⁻ᵀ_iL F⁻ᵀ_kJ + λ F⁻ᵀ_iJ F⁻ᵀ_kL, MPa."""
        with np.errstate(all="ignore"):
            return self.tangent_terms(F).full()

    def tangent_terms(self, F) -> TangentTerms:
        """The tangent as kron μ(δ, δ) + dyad (λG, G) + cross ((μ − λ ln J)G, G), G = F⁻ᵀ."""
        F = as_tensor_field(F)
        with np.errstate(all="ignore"):
            G, J = inv_transpose(F)
            c = self.mu - self.lmbda * np.log(J)
        return TangentTerms(F.shape[2:], kron=[(self.mu, 1.0)], dyad=[((self.lmbda, G), G)],
                            cross=[((c, G), G)])
