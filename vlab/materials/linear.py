"""Linear (small-strain) isotropic elasticity — generalised Hooke's law.

NOT objective: ε = sym(F − I) changes under a rigid rotation, so a rotated, unstrained body
carries spurious stress. Use it only where rotations are small.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.base import Material
from vlab.materials.structure import TangentTerms
from vlab.tensor import as_tensor_field, identity_like, trace

__all__ = ["LinearElastic"]

_I = np.eye(3)
#: I⊗I, (I⊗I)_iJkL = δ_iJ δ_kL
_II = np.einsum("ij,kl->ijkl", _I, _I)
#: δ_ik δ_JL + δ_iL δ_Jk
_SYM = np.einsum("ik,jl->ijkl", _I, _I) + np.einsum("il,jk->ijkl", _I, _I)
for _a in (_II, _SYM):
    _a.setflags(write=False)


@dataclass(frozen=True)
class LinearElastic(Material):
    """Small-strain isotropic linear elasticity (quadratic energy; one Newton step is exact).

    With ε = sym(F − I) = ½((F − I) + (F − I)ᵀ), shape (3,3,*batch):

    - ψ = ½λ (tr ε)² + μ tr(ε²)                       shape (*batch), MPa
    - P = λ tr(ε) I + 2μ ε                            shape (3,3,*batch), MPa (symmetric)
    - A_iJkL = λ δ_iJ δ_kL + μ(δ_ik δ_JL + δ_iL δ_Jk)  shape (3,3,3,3,*batch), MPa, constant

    No restriction on J: the energy is finite for any F (including inverted ones).
    """

    name: ClassVar[str] = "linear"
    is_linear: ClassVar[bool] = True

    @staticmethod
    def _strain(F: np.ndarray) -> np.ndarray:
        eps = F + np.swapaxes(F, 0, 1)
        eps *= 0.5
        for i in range(3):
            eps[i, i] -= 1.0
        return eps

    def energy(self, F) -> np.ndarray:
        """ψ = ½λ(tr ε)² + μ ε:ε, shape (*batch), MPa."""
        eps = self._strain(as_tensor_field(F))
        tr = trace(eps)
        return 0.5 * self.lmbda * tr * tr + self.mu * np.einsum("ij...,ij...->...", eps, eps)

    def stress(self, F) -> np.ndarray:
        """P = λ tr(ε) I + 2μ ε, shape (3,3,*batch), MPa."""
        eps = self._strain(as_tensor_field(F))
        ltr = self.lmbda * trace(eps)
        P = eps
        P *= 2.0 * self.mu
        for i in range(3):
            P[i, i] += ltr
        return P

    def tangent(self, F) -> np.ndarray:
        """A = λ I⊗I + μ(δ_ik δ_JL + δ_iL δ_Jk), shape (3,3,3,3,*batch), MPa (a new array)."""
        F = as_tensor_field(F)
        C = self.lmbda * _II + self.mu * _SYM
        batch = F.shape[2:]
        return np.broadcast_to(C.reshape(C.shape + (1,) * len(batch)), C.shape + batch).copy()

    def tangent_terms(self, F) -> TangentTerms:
        """kron μ(δ, δ) + dyad (λI, I) + cross (μI, I)."""
        identity = identity_like(as_tensor_field(F))
        return TangentTerms(identity.shape[2:], kron=[(self.mu, 1.0)],
                            dyad=[((self.lmbda, identity), identity)],
                            cross=[((self.mu, identity), identity)])
