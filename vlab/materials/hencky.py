"""Hencky (logarithmic-strain) hyperelasticity: the elastic law of the J2 plasticity model.

With the principal stretches λ_A of F and the log strains ε_A = ln λ_A (Hencky strain
ln V = Σ ε_A n_A ⊗ n_A), λ, μ the Lamé constants (MPa) and K = λ + 2μ/3:

    ψ = ½ λ (tr ε)² + μ ε:ε = ½ K (tr ε)² + μ |dev ε|²           (*batch), MPa
    τ_A = ∂ψ/∂ε_A = λ tr ε + 2μ ε_A                             principal Kirchhoff stress
    c_AB = ∂τ_A/∂ε_B = λ + 2μ δ_AB,   g_AB = (τ_A − τ_B)/(ε_A − ε_B) = 2μ

P and A follow from vlab.materials.principal. The Kirchhoff stress is *linear* in the log
strain, τ = λ tr(ε) I + 2μ ε, so in uniaxial stress τ₁₁ = E ln λ₁ exactly at any stretch: the
property that makes the 1D plasticity oracle (vlab.materials.plasticity) exact in log strain.
ψ = +inf and P, A = nan where det F ≤ 0. Not in the scene's model registry (yet): it serves as
the elastic part of ``effects.plasticity``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.base import Material
from vlab.materials.principal import principal_frame, principal_stress, principal_tangent
from vlab.tensor import as_tensor_field, det, identity_like

__all__ = ["Hencky", "admissible_part"]


def admissible_part(F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F with the identity where det F ≤ 0, mask det F > 0): keeps eigh away from bad points."""
    ok = det(F) > 0.0
    return np.where(ok, F, identity_like(F)), ok


@dataclass(frozen=True)
class Hencky(Material):
    """ψ = ½λ(tr ln V)² + μ |ln V|² (module docstring)."""

    name: ClassVar[str] = "hencky"
    is_linear: ClassVar[bool] = False

    def principal(self, eps: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(ψ, τ_A, c_AB, g_AB) from the principal log strains ε (3,*batch)."""
        tr = eps.sum(axis=0)
        psi = 0.5 * self.lmbda * tr**2 + self.mu * np.sum(eps**2, axis=0)
        tau = self.lmbda * tr + 2.0 * self.mu * eps
        shape = (3, 3) + eps.shape[1:]
        c = np.full(shape, self.lmbda) + 2.0 * self.mu * np.eye(3).reshape((3, 3) + (1,) * (eps.ndim - 1))
        return psi, tau, c, np.full(shape, 2.0 * self.mu)

    def energy(self, F) -> np.ndarray:
        Fa, ok = admissible_part(as_tensor_field(F))
        psi = self.principal(principal_frame(Fa).eps)[0]
        return np.where(ok, psi, np.inf)

    def stress(self, F) -> np.ndarray:
        Fa, ok = admissible_part(as_tensor_field(F))
        frame = principal_frame(Fa)
        return np.where(ok, principal_stress(frame, self.principal(frame.eps)[1]), np.nan)

    def tangent(self, F) -> np.ndarray:
        Fa, ok = admissible_part(as_tensor_field(F))
        frame = principal_frame(Fa)
        _, tau, c, g = self.principal(frame.eps)
        return np.where(ok, principal_tangent(frame, tau, c, g), np.nan)
