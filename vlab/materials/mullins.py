"""Ogden–Roxburgh pseudo-elastic model of the Mullins effect over a hyperelastic ground law.

Ground law ψ₀(F) (the scene's model, e.g. vlab's Neo-Hookean), state W_max ≥ 0: the largest
ψ₀ reached at the point (MPa; virgin 0). With the parameters r > 1, m > 0 (MPa), β ≥ 0 and

    z = max(0, (W_max − ψ₀)/(m + β W_max)),     η = 1 − erf(z)/r   ∈ (1 − 1/r, 1],

the pseudo-energy (Ogden & Roxburgh 1999) is ψ = η ψ₀ + φ(η), with φ chosen so ∂ψ/∂η = 0:
φ'(η) = −ψ₀(η) = −W_max + (m + βW_max) erfinv(r(1 − η)), φ(1) = 0, hence in closed form

    φ(η) = (1 − η) W_max − (m + βW_max)/(r√π) · (1 − exp(−erfinv(r(1 − η))²)),

(using ∫₀ˣ erfinv(u) du = (1 − exp(−erfinv(x)²))/√π). Since erfinv(r(1 − η)) = z,
ψ = η ψ₀ + (1 − η) W_max − (m + βW_max)(1 − e^(−z²))/(r√π). Derivatives (∂ψ/∂η = 0):

    P = η P₀,       A = η A₀ + η' P₀ ⊗ P₀,      η' = dη/dψ₀ = 2 e^(−z²)/(r√π (m + βW_max))

on unloading/reloading below the maximum (ψ₀ < W_max); on the primary path (ψ₀ ≥ W_max) η = 1,
η' = 0 and everything equals the ground law. At the turning point ψ₀ = W_max: η = 1 − erf(0)/r = 1,
P is continuous, the tangent jumps by η' P₀⊗P₀ (ψ is C¹, not C², there). The largest softening
at rest after a maximum W_max is η(ψ₀ = 0) = 1 − erf(W_max/(m + βW_max))/r.

Pseudo-elastic: unloading and reloading below W_max follow the same curve, below the primary
curve, and rejoin it beyond the previous maximum. Rate-independent: ``dt`` is ignored.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.history import HistoryMaterial, Response, State
from vlab.tensor import as_tensor_field, dyad

__all__ = ["OgdenRoxburgh"]

_SQRT_PI = math.sqrt(math.pi)


# scipy.special takes ~0.15 s to import (its array-API layer): imported on first use, so only a
# scene with Mullins softening pays it
def _erf(x):
    from scipy.special import erf

    return erf(x)


def _erfinv(x):
    from scipy.special import erfinv

    return erfinv(x)


@dataclass(frozen=True)
class OgdenRoxburgh(HistoryMaterial):
    """Mullins softening η ψ₀ + φ(η) (module docstring); ``elastic`` is the ground law ψ₀."""

    r: float = 2.0        # > 1: the largest softening is 1/r
    m: float = 1.0        # > 0, MPa: energy scale of the softening
    beta: float = 0.0     # ≥ 0: growth of that scale with W_max

    name: ClassVar[str] = "mullins"

    def __post_init__(self) -> None:
        if not (self.r > 1.0 and self.m > 0.0 and self.beta >= 0.0):
            raise ValueError(f"OgdenRoxburgh: need r > 1, m > 0, beta >= 0; got r={self.r}, m={self.m}, "
                             f"beta={self.beta}")

    def initial_state(self, batch: tuple[int, ...]) -> State:
        return {"W_max": np.zeros(tuple(batch))}

    def scale(self, W_max):
        """m + β W_max, MPa."""
        return self.m + self.beta * W_max

    def softening(self, psi0, W_max) -> np.ndarray:
        """η = 1 − erf(z)/r, z = max(0, (W_max − ψ₀)/(m + βW_max))."""
        return 1.0 - _erf(self._z(psi0, W_max)) / self.r

    def phi(self, eta, W_max) -> np.ndarray:
        """φ(η) = (1 − η)W_max − (m + βW_max)(1 − exp(−erfinv(r(1 − η))²))/(r√π), MPa."""
        y = _erfinv(self.r * (1.0 - np.asarray(eta, dtype=float)))
        return (1.0 - eta) * W_max - self.scale(W_max) * (-np.expm1(-y * y)) / (self.r * _SQRT_PI)

    def respond(self, F, state: State, dt: float, with_tangent: bool = True) -> Response:
        F = as_tensor_field(F)
        W_max = np.asarray(state["W_max"], dtype=float)
        psi0, P0 = self.elastic.energy(F), self.elastic.stress(F)
        finite = np.isfinite(psi0)
        psi0_ok = np.where(finite, psi0, 0.0)
        z = self._z(psi0_ok, W_max)
        eta = 1.0 - _erf(z) / self.r
        energy = eta * psi0_ok + (1.0 - eta) * W_max - self.scale(W_max) * (-np.expm1(-z * z)) / (
            self.r * _SQRT_PI)
        energy = np.where(finite, energy, np.inf)
        A = None
        if with_tangent:
            deta = np.where(psi0_ok < W_max, 2.0 * np.exp(-z * z) / (self.r * _SQRT_PI * self.scale(W_max)), 0.0)
            A = eta * self.elastic.tangent(F)
            dyad(deta * P0, P0, out=A)
        return Response(energy=energy, stress=eta * P0, tangent=A)

    def update(self, F, state: State, dt: float) -> State:
        psi0 = self.elastic.energy(as_tensor_field(F))
        W_max = np.asarray(state["W_max"], dtype=float)
        return {"W_max": np.where(np.isfinite(psi0), np.maximum(W_max, psi0), W_max)}

    def history_fields(self, state: State, F=None) -> dict[str, np.ndarray]:
        """Scalar history per point for output: W_max (MPa) and, at deformation F, the softening
        η (1 on the primary curve; 1 at the virgin state when F is None)."""
        W_max = np.asarray(state["W_max"], dtype=float)
        if F is None:
            return {"max_energy": W_max, "softening": np.ones_like(W_max)}
        psi0 = self.elastic.energy(as_tensor_field(F))
        eta = self.softening(np.where(np.isfinite(psi0), psi0, W_max), W_max)
        return {"max_energy": W_max, "softening": eta}

    def _z(self, psi0, W_max):
        return np.maximum(0.0, (W_max - psi0) / self.scale(W_max))
