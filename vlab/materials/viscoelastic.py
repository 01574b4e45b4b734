"""Finite-strain viscoelasticity: a Prony series of Maxwell branches on the isochoric part.

Simo (1987), in the form of Holzapfel, *Nonlinear Solid Mechanics* (2000), §6.10. The second
Piola–Kirchhoff stress is the elastic ground law's plus non-equilibrium stresses Q_i (MPa),

    S = S∞(C) + Σ_i Q_i,      Q̇_i + Q_i / τ_i = β_i Ṡ_iso,      Q_i(0) = 0,

with relaxation times τ_i (s), relative moduli β_i ≥ 0 (dimensionless, relative to the ground
law's shear stiffness) and the isochoric Neo-Hookean stress of the ground shear modulus μ,

    ψ_iso(C̄) = ½ μ (tr C̄ − 3),  C̄ = J^(−2/3) C,   S_iso = 2 ∂ψ_iso/∂C = μ J^(−2/3) (I − ⅓ tr C C⁻¹).

So the instantaneous shear modulus is μ (1 + Σβ_i) and the long-term one μ: a held strain relaxes
to the ground law, the relaxation function of shear is μ (1 + Σ β_i e^(−t/τ_i)).

Time integration (midpoint rule of the convolution integral; Holzapfel eq. 6.166): with
ξ_i = exp(−Δt / 2τ_i) and the frozen history stress H_i^n = ξ_i (ξ_i Q_i^n − β_i S_iso^n),

    Q_i^{n+1} = H_i^n + β_i ξ_i S_iso^{n+1}.

For fixed state n and Δt this stress derives from the incremental potential (MPa)

    ψ_inc(F) = ψ∞(F) + γ ψ_iso(C̄) + H : E,    γ = Σ β_i ξ_i,  H = Σ H_i^n,  E = ½(C − I),

    P = ∂ψ_inc/∂F = P∞ + F (γ S_iso + H),
    A = A∞ + δ_ik (γ S_iso + H)_JL + γ F_iI ℂ_iso,IJKL F_kK,
    ℂ_iso = 2 ∂S_iso/∂C = 2μJ^(−2/3)[−⅓ I⊗C⁻¹ − ⅓ C⁻¹⊗I + (tr C/9) C⁻¹⊗C⁻¹ + (tr C/3) C⁻¹⊙C⁻¹],

the push-forward written with G = F⁻ᵀ (F C⁻¹ = G, F C⁻¹ Fᵀ = I). The state is {"Q": Q_i^n
(m, 3, 3, *batch), "S_iso": S_iso^n (3, 3, *batch)}. β = 0 gives back the ground law exactly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.history import HistoryMaterial, Response, State
from vlab.tensor import dot, dyad, dyad_ik, dyad_il, identity_like, inv_transpose, transpose


@dataclass(frozen=True)
class PronyViscoelastic(HistoryMaterial):
    """Maxwell branches (τ_i s, β_i) on the isochoric Neo-Hookean part of ``elastic``."""

    tau: tuple[float, ...] = ()
    beta: tuple[float, ...] = ()

    name: ClassVar[str] = "viscoelastic"

    def __post_init__(self) -> None:
        if len(self.tau) != len(self.beta) or not self.tau:
            raise ValueError(f"viscoelastic: tau and beta need the same, nonzero length, got "
                             f"{len(self.tau)} and {len(self.beta)}")
        if min(self.tau) <= 0 or min(self.beta) < 0:
            raise ValueError(f"viscoelastic: tau must be > 0 and beta >= 0, got {self.tau}, {self.beta}")

    def initial_state(self, batch: tuple[int, ...]) -> State:
        m = len(self.tau)
        return {"Q": np.zeros((m, 3, 3) + tuple(batch)), "S_iso": np.zeros((3, 3) + tuple(batch))}

    def _xi(self, dt: float) -> np.ndarray:
        return np.exp(-float(dt) / (2.0 * np.asarray(self.tau)))

    def _history(self, state: State, xi: np.ndarray) -> np.ndarray:
        """H = Σ_i ξ_i (ξ_i Q_i^n − β_i S_iso^n), (3, 3, *batch)."""
        beta = np.asarray(self.beta)
        shape = (-1,) + (1,) * (state["Q"].ndim - 1)
        return (xi.reshape(shape) ** 2 * state["Q"]).sum(axis=0) - float(xi @ beta) * state["S_iso"]

    def _iso(self, F: np.ndarray):
        """S_iso, ψ_iso and the pieces of ℂ_iso: (S_iso, ψ_iso, a = J^(−2/3), tr C, G = F⁻ᵀ)."""
        G, J = inv_transpose(F)
        a = J ** (-2.0 / 3.0)
        trC = np.einsum("ij...,ij...->...", F, F)
        Cinv = dot(transpose(G), G)  # C⁻¹ = F⁻¹ F⁻ᵀ
        S_iso = self.elastic.mu * a * (identity_like(F) - trC / 3.0 * Cinv)
        psi_iso = 0.5 * self.elastic.mu * (a * trC - 3.0)
        return S_iso, psi_iso, a, trC, G, Cinv

    def respond(self, F: np.ndarray, state: State, dt: float, with_tangent: bool = True) -> Response:
        xi = self._xi(dt)
        gamma = float(xi @ np.asarray(self.beta))
        H = self._history(state, xi)
        with np.errstate(all="ignore"):
            S_iso, psi_iso, a, trC, G, Cinv = self._iso(F)
            E = 0.5 * (dot(transpose(F), F) - identity_like(F))
            energy = self.elastic.energy(F) + gamma * psi_iso + np.einsum("ij...,ij...->...", H, E)
            S_v = gamma * S_iso + H
            stress = self.elastic.stress(F) + dot(F, S_v)
            tangent = None
            if with_tangent:
                tangent = self.elastic.tangent(F)
                dyad_ik(identity_like(F), S_v, out=tangent)              # δ_ik S_v,JL
                c = 2.0 * self.elastic.mu * gamma * a                      # γ F ℂ_iso F, pushed forward
                dyad(-c / 3.0 * F, G, out=tangent)
                dyad(-c / 3.0 * G, F, out=tangent)
                dyad(c * trC / 9.0 * G, G, out=tangent)
                dyad_ik(identity_like(F), c * trC / 6.0 * Cinv, out=tangent)
                dyad_il(c * trC / 6.0 * G, transpose(G), out=tangent)
        return Response(energy, stress, tangent)

    def update(self, F: np.ndarray, state: State, dt: float) -> State:
        xi = self._xi(dt)
        beta = np.asarray(self.beta)
        shape = (-1,) + (1,) * (state["Q"].ndim - 1)
        with np.errstate(all="ignore"):
            S_iso = self._iso(F)[0]
        H_i = xi.reshape(shape) * (xi.reshape(shape) * state["Q"] - beta.reshape(shape) * state["S_iso"])
        return {"Q": H_i + (beta * xi).reshape(shape) * S_iso, "S_iso": S_iso}

    def history_fields(self, state: State, F=None) -> dict[str, np.ndarray]:
        """Scalar history per point for output: ‖Σ Q_i‖ (MPa), the non-equilibrium stress."""
        Q = state["Q"].sum(axis=0)
        return {"viscous_stress": np.sqrt(np.einsum("ij...,ij...->...", Q, Q))}
