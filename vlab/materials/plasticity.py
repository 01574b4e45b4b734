"""Finite-strain J2 plasticity with isotropic (linear + Voce) hardening, Hencky elasticity.

Kinematics: multiplicative split F = F_e F_p with plastic incompressibility (det F_p = 1).
State per point: the inverse plastic right Cauchy–Green tensor C_p⁻¹ = F_p⁻¹F_p⁻ᵀ (3,3,*batch)
and the accumulated (equivalent) plastic strain α ≥ 0 (*batch). Virgin state: C_p⁻¹ = I, α = 0.

Elastic law: Hencky, ψ_e = ½K (tr ε_e)² + μ|dev ε_e|², ε_e = ½ ln b_e, b_e = F C_p⁻¹ Fᵀ, with the
Lamé constants of the ground law (K = λ + 2μ/3). Kirchhoff stress τ = K tr(ε_e) I + 2μ dev ε_e.

Yield: f = q − σ_y(α) ≤ 0 with the von Mises stress q = √(3/2)|dev τ| and the flow stress

    σ_y(α) = σ_y0 + H α + Q (1 − e^(−δα))          (MPa; Q = 0: linear hardening)

Return map (Simo 1992, exponential map; backward Euler, exact for a fixed flow direction):
with L Lᵀ = C_p⁻¹ₙ (Cholesky) the trial elastic stretch is F̄ = F L (b_eᵗʳ = F̄ F̄ᵀ), with
principal log strains εᵗʳ_A and deviator eᵗʳ. If qᵗʳ = √6 μ|eᵗʳ| > σ_y(αₙ) the increment Δα
solves the scalar equation (Newton, monotone from Δα = 0 as it is convex and decreasing)

    qᵗʳ − 3μ Δα − σ_y(αₙ + Δα) = 0,

and the deviator is scaled radially: e = β eᵗʳ, β = 1 − 3μΔα/qᵗʳ (β = 1 if elastic). Update:
C_p⁻¹ₙ₊₁ = L [Σ_A exp(−2(1 − β) eᵗʳ_A) N_A ⊗ N_A] Lᵀ (det preserved = 1), αₙ₊₁ = αₙ + Δα.

Incremental potential (the return map is its minimiser over the plastic increment, so P is
its derivative at the returned state):

    ψ_inc(F) = ψ_e(ε) + D(αₙ + Δα) − D(αₙ),
    D(α) = σ_y0 α + ½H α² + Q (α − (1 − e^(−δα))/δ),   D'(α) = σ_y(α),

    P = ∂ψ_inc/∂F = P̄ Lᵀ,  P̄ = Σ_A (τ_A/λ_A) n_A ⊗ N_A,     A_iJkL = Ā_iKkM L_JK L_LM,

with Ā from vlab.materials.principal and the consistent principal moduli (n̂ = eᵗʳ/|eᵗʳ|, h = σ_y'):

    c = K 1⊗1 + 2μβ I_dev + γ n̂⊗n̂,   γ = 2μ(1 − β) − 6μ²/(3μ + h) (plastic; 0 if elastic),
    g_AB = (τ_A − τ_B)/(εᵗʳ_A − εᵗʳ_B) = 2μβ.

In the elastic range (Δα = 0) every quantity equals vlab.materials.hencky exactly.
1D oracle (uniaxial stress, monotonic, checked in tests/test_plasticity.py): τ₁₁ = σ_y(α) and
ln λ₁ = α + τ₁₁/E, so the tangent slope in τ–ln λ is E h/(E + h) and unloading to τ = 0
leaves the permanent log strain α = ln λ_max − τ_max/E, exactly and for any step size.
Rate-independent: ``dt`` is accepted for the interface and ignored.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from vlab.materials.hencky import Hencky, admissible_part
from vlab.materials.history import HistoryMaterial, Response, State
from vlab.materials.principal import PrincipalFrame, principal_frame, principal_stress, principal_tangent
from vlab.tensor import as_tensor_field

__all__ = ["J2Plasticity"]

_NEWTON_MAX = 60
_NEWTON_RTOL = 1e-14
_SQRT6 = np.sqrt(6.0)


class _Return(NamedTuple):
    """The trial state and its return map at every point."""

    ok: np.ndarray          # det F > 0
    L: np.ndarray           # Cholesky factor of C_p⁻¹ₙ
    frame: PrincipalFrame   # principal frame of F̄ = F L
    tr: np.ndarray          # tr εᵗʳ = ln J
    e: np.ndarray           # trial deviator eᵗʳ (3,*b)
    plastic: np.ndarray     # yielding points
    dalpha: np.ndarray      # Δα
    beta: np.ndarray        # radial scaling of the deviator


@dataclass(frozen=True)
class J2Plasticity(HistoryMaterial):
    """J2 plasticity (module docstring). Stresses in MPa, α and δ·α dimensionless.

    ``elastic`` must be a Hencky law; build one from any ground law with
    :func:`vlab.effects.plasticity.parse_params` or ``J2Plasticity(Hencky(m.lmbda, m.mu), ...)``.
    """

    yield_stress: float = 1.0          # σ_y0 > 0, MPa
    hardening_modulus: float = 0.0     # H ≥ 0, MPa
    saturation_stress: float = 0.0     # Q ≥ 0, MPa (Voce increase of the flow stress)
    saturation_exponent: float = 0.0   # δ > 0 when Q > 0

    name: ClassVar[str] = "plasticity"

    def __post_init__(self) -> None:
        if not isinstance(self.elastic, Hencky):
            raise TypeError(f"J2Plasticity needs a Hencky elastic law, got {type(self.elastic).__name__}")
        if not self.yield_stress > 0.0 or self.hardening_modulus < 0.0 or self.saturation_stress < 0.0:
            raise ValueError("J2Plasticity: need yield_stress > 0, hardening_modulus >= 0, saturation_stress >= 0")
        if self.saturation_stress > 0.0 and not self.saturation_exponent > 0.0:
            raise ValueError("J2Plasticity: saturation_exponent must be > 0 when saturation_stress > 0")

    # --- hardening law -----------------------------------------------------------------------
    def flow_stress(self, alpha):
        """σ_y(α) = σ_y0 + Hα + Q(1 − e^(−δα)), MPa."""
        return (self.yield_stress + self.hardening_modulus * alpha
                - self.saturation_stress * np.expm1(-self.saturation_exponent * alpha))

    def hardening_slope(self, alpha):
        """h = σ_y'(α) = H + Qδ e^(−δα), MPa."""
        return self.hardening_modulus + self.saturation_stress * self.saturation_exponent * np.exp(
            -self.saturation_exponent * alpha)

    def dissipation_increment(self, alpha_n, dalpha):
        """D(αₙ + Δα) − D(αₙ) = ∫ σ_y dα over the increment, MPa."""
        H, Q, d = self.hardening_modulus, self.saturation_stress, self.saturation_exponent
        sat = 0.0 if Q == 0.0 else Q * (dalpha + np.exp(-d * alpha_n) * np.expm1(-d * dalpha) / d)
        return self.yield_stress * dalpha + H * (alpha_n * dalpha + 0.5 * dalpha**2) + sat

    # --- HistoryMaterial interface -------------------------------------------------------------
    def initial_state(self, batch: tuple[int, ...]) -> State:
        Cp_inv = np.zeros((3, 3) + tuple(batch))
        for i in range(3):
            Cp_inv[i, i] = 1.0
        return {"Cp_inv": Cp_inv, "alpha": np.zeros(tuple(batch))}

    def respond(self, F, state: State, dt: float, with_tangent: bool = True) -> Response:
        r = self._return(F, state)
        mu, K = self.elastic.mu, self.elastic.bulk_modulus
        tau = K * r.tr + 2.0 * mu * r.beta * r.e
        energy = (0.5 * K * r.tr**2 + mu * r.beta**2 * np.sum(r.e**2, axis=0)
                  + self.dissipation_increment(state["alpha"], r.dalpha))
        energy = np.where(r.ok, energy, np.inf)
        P = np.einsum("iK...,JK...->iJ...", principal_stress(r.frame, tau), r.L)
        P = np.where(r.ok, P, np.nan)
        A = None
        if with_tangent:
            c, g = self._moduli(r, state["alpha"])
            A = principal_tangent(r.frame, tau, c, g, right=r.L)  # Ā_iKkM L_JK L_LM
            A = np.where(r.ok, A, np.nan)
        return Response(energy=energy, stress=P, tangent=A)

    def update(self, F, state: State, dt: float) -> State:
        r = self._return(F, state)
        N = r.frame.N
        plastic_factor = np.einsum("A...,IA...,JA...->IJ...", np.exp(-2.0 * (1.0 - r.beta) * r.e), N, N)
        Cp_inv = np.einsum("IK...,KM...,JM...->IJ...", r.L, plastic_factor, r.L)
        Cp_inv = 0.5 * (Cp_inv + np.swapaxes(Cp_inv, 0, 1))
        keep = r.ok  # an inadmissible point (never accepted by the solver) keeps its state
        return {"Cp_inv": np.where(keep, Cp_inv, state["Cp_inv"]),
                "alpha": np.where(keep, state["alpha"] + r.dalpha, state["alpha"])}

    def history_fields(self, state: State, F=None) -> dict[str, np.ndarray]:
        """Scalar history per point for output: the accumulated plastic strain α (1)."""
        return {"plastic_strain": np.asarray(state["alpha"], dtype=float)}

    # --- internals ------------------------------------------------------------------------------
    def _return(self, F, state: State) -> _Return:
        F, ok = admissible_part(as_tensor_field(F))
        Cp_inv = np.asarray(state["Cp_inv"], dtype=float)
        L = np.moveaxis(np.linalg.cholesky(np.moveaxis(Cp_inv, (0, 1), (-2, -1))), (-2, -1), (0, 1))
        frame = principal_frame(np.einsum("iJ...,JK...->iK...", F, L))
        tr = frame.eps.sum(axis=0)
        e = frame.eps - tr / 3.0
        mu = self.elastic.mu
        q_trial = _SQRT6 * mu * np.sqrt(np.sum(e**2, axis=0))
        alpha_n = np.asarray(state["alpha"], dtype=float)
        plastic = ok & (q_trial > self.flow_stress(alpha_n))
        dalpha = self._solve_increment(np.where(plastic, q_trial, 0.0), alpha_n, plastic)
        beta = np.where(plastic, 1.0 - 3.0 * mu * dalpha / np.where(plastic, q_trial, 1.0), 1.0)
        return _Return(ok, L, frame, tr, e, plastic, dalpha, beta)

    def _solve_increment(self, q_trial, alpha_n, plastic) -> np.ndarray:
        """Δα with q − 3μΔα − σ_y(αₙ + Δα) = 0 on plastic points, 0 elsewhere."""
        mu3 = 3.0 * self.elastic.mu
        dalpha = np.zeros_like(q_trial)
        scale = self.yield_stress + q_trial
        for _ in range(_NEWTON_MAX):
            residual = np.where(plastic, q_trial - mu3 * dalpha - self.flow_stress(alpha_n + dalpha), 0.0)
            dalpha = dalpha + residual / (mu3 + self.hardening_slope(alpha_n + dalpha))
            if np.all(np.abs(residual) <= _NEWTON_RTOL * scale):
                return dalpha
        raise RuntimeError("J2 return map did not converge")  # pragma: no cover - convex scalar root

    def _moduli(self, r: _Return, alpha_n) -> tuple[np.ndarray, np.ndarray]:
        """Consistent principal moduli c_AB (3,3,*b) and g_AB = 2μβ."""
        mu, K = self.elastic.mu, self.elastic.bulk_modulus
        bshape = (1,) * r.beta.ndim
        eye = np.eye(3).reshape((3, 3) + bshape)
        c = K * np.ones((3, 3) + bshape) + 2.0 * mu * r.beta * (eye - 1.0 / 3.0)
        norm = np.sqrt(np.sum(r.e**2, axis=0))
        nhat = r.e / np.where(r.plastic, norm, 1.0)
        h = self.hardening_slope(alpha_n + r.dalpha)
        gamma = np.where(r.plastic, 2.0 * mu * (1.0 - r.beta) - 6.0 * mu**2 / (3.0 * mu + h), 0.0)
        c = c + gamma * nhat[:, None] * nhat[None, :]
        return c, np.broadcast_to(2.0 * mu * r.beta, c.shape).copy()
