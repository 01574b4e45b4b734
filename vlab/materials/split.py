"""Volumetric–isochoric split laws for the mixed (mean-dilatation type) formulation.

A split law writes the strain energy as an isochoric part plus a function of one scalar
*volume measure* v(F):

    ψ(F) = ψ_iso(F) + U(v(F))

where ψ_iso does not change under a pure dilatation. v is the volume *change* (J − 1, or tr ε),
computed without forming 1 + small − 1: near ν = ½ the volumetric energy is κ times the square
of a tiny number, and the energy line search needs it to full relative precision. The mixed body (vlab/fe/mixed.py) replaces
v by θ, its L2 projection on a discontinuous element space, so the volumetric constraint is
imposed once per element (or per linear mode of an element) instead of at every quadrature
point — that is what removes volumetric locking.

Each law here is also a complete :class:`Material` whose ``energy/stress/tangent`` are those of
ψ(F) with θ = v pointwise: the one-field law the mixed body reduces to for a homogeneous state,
used for the analytic oracles (block tests) and for stresses in post-processing.

Small strain: with F = I + ε, ψ_iso ≈ μ dev ε : dev ε and U ≈ κ/2 (tr ε)², so
ψ ≈ μ ε:ε + ½(κ − 2μ/3)(tr ε)² — Hooke's law with λ = κ − 2μ/3, i.e. κ = K = λ + 2μ/3 is the
bulk modulus of the scene's (E, ν): the same small-strain E and ν as the displacement model.

Models without a natural split (St. Venant–Kirchhoff: μ tr E² holds volumetric strain too) have
no ``split`` in the model registry (vlab.materials.registry); the scene refuses ``mesh.formulation = "mixed"`` for them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.base import Material
from vlab.materials.linear import LinearElastic
from vlab.tensor import as_tensor_field, det, dyad, dyad_il, inv_transpose, transpose

__all__ = ["OneFieldSplit", "SplitNeoHookean", "SplitLinear"]


def _add_identity_ik_jl(A: np.ndarray, scale) -> None:
    """A_iJkL += scale δ_ik δ_JL (in place)."""
    for i in range(3):
        for j in range(3):
            A[i, j, i, j] += scale


class OneFieldSplit:
    """The one-field law of a split law (θ = v(F) pointwise), for any class that supplies the split
    pieces ``volume`` v, ``volume_gradient`` ∂v/∂F, ``volume_hessian`` ∂²v/∂F∂F, ``U``, ``dU``,
    ``d2U`` (of the volume change x = v) and ``isochoric_energy/stress/tangent``:

        ψ = ψ_iso(F) + U(v),    P = P_iso + U'(v) ∂v/∂F,
        A = A_iso + U''(v) (∂v/∂F ⊗ ∂v/∂F) + U'(v) ∂²v/∂F∂F        (MPa).

    Shared by :class:`SplitNeoHookean` and the rubber models' frame
    (vlab.materials.isochoric.IsochoricVolumetric). ``_tangent_errstate``: numpy's error handling
    while the volumetric terms are added to A (the rubber frame ignores them: past J <= 0 or a
    locking limit the terms are inf/nan by design, and ψ = +inf there makes the line search reject
    the step)."""

    _tangent_errstate: ClassVar[dict] = {}

    def energy(self, F) -> np.ndarray:
        """ψ = ψ_iso(F) + U(v(F)), +inf where J <= 0 (or past a locking limit), MPa."""
        F = as_tensor_field(F)
        return self.isochoric_energy(F) + self.U(self.volume(F))

    def stress(self, F) -> np.ndarray:
        """P = P_iso + U'(v) ∂v/∂F (∂J/∂F = J F⁻ᵀ), MPa."""
        F = as_tensor_field(F)
        return self.isochoric_stress(F) + self.dU(self.volume(F)) * self.volume_gradient(F)

    def tangent(self, F) -> np.ndarray:
        """A = A_iso + U''(v) (∂v/∂F ⊗ ∂v/∂F) + U'(v) ∂²v/∂F∂F, MPa."""
        F = as_tensor_field(F)
        x = self.volume(F)
        V = self.volume_gradient(F)
        A = self.isochoric_tangent(F)
        with np.errstate(**self._tangent_errstate):
            dyad(self.d2U(x) * V, V, out=A)
            A += self.dU(x) * self.volume_hessian(F)
        return A


@dataclass(frozen=True)
class SplitNeoHookean(OneFieldSplit, Material):
    """Neo-Hookean with a volumetric–isochoric split (Simo–Taylor–Pister type, as in Holzapfel
    §6.5 and deal.II step-44 / the Cook's membrane code gallery).

    With J = det F, I₁ = F:F, G = F⁻ᵀ, κ = λ + 2μ/3 (MPa):

    - ψ_iso = ½μ (J^(−2/3) I₁ − 3)
    - U(θ)  = ¼κ (θ² − 1 − 2 ln θ),  U' = ½κ (θ − 1/θ),  U'' = ½κ (1 + 1/θ²) > 0 (convex),
      U → +∞ as θ → 0⁺; written in the volume change x = θ − 1 (methods take x):
      U = ¼κ (2x + x² − 2 log1p x), U' = ½κ x(2 + x)/(1 + x), U'' = ½κ (1 + 1/(1 + x)²);
      volume change v(F) = J − 1 = tr H + ½((tr H)² − H:Hᵀ) + det H with H = F − I.
    - P_iso = μ J^(−2/3) (F − I₁/3 G)
    - A_iso = μ J^(−2/3) [δ_ik δ_JL − ⅔(F⊗G + G⊗F) + (2/9) I₁ G⊗G + (I₁/3) G_iL G_kJ]
    - ∂J/∂F = J G,  ∂²J/∂F∂F = J (G⊗G − G_iL G_kJ)

    It agrees with :class:`NeoHookean` (ψ = ½μ(I₁ − 3) − μ ln J + ½λ ln²J) to second order at
    F = I (same E, ν) and differs at finite strain (a different volumetric function).
    """

    name: ClassVar[str] = "neo-hookean-split"
    is_linear: ClassVar[bool] = False
    theta_min: ClassVar[float] = 0.0  # U(θ) = +inf for θ <= 0 (x <= −1)

    @property
    def kappa(self) -> float:
        return self.bulk_modulus

    # --- the split pieces ------------------------------------------------------------------
    def volume(self, F: np.ndarray) -> np.ndarray:
        """v(F) = J − 1 from the invariants of H = F − I (no cancellation), shape (*batch)."""
        H = as_tensor_field(F).copy()
        for i in range(3):
            H[i, i] -= 1.0
        tr = H[0, 0] + H[1, 1] + H[2, 2]
        return tr + 0.5 * (tr * tr - np.einsum("ij...,ji...->...", H, H)) + det(H)

    def volume_gradient(self, F: np.ndarray) -> np.ndarray:
        """∂J/∂F = J F⁻ᵀ, shape (3,3,*batch)."""
        with np.errstate(all="ignore"):
            G, J = inv_transpose(as_tensor_field(F))
        return G * J

    def volume_hessian(self, F: np.ndarray) -> np.ndarray:
        """∂²J/∂F_iJ∂F_kL = J (G_iJ G_kL − G_iL G_kJ), shape (3,3,3,3,*batch)."""
        with np.errstate(all="ignore"):
            G, J = inv_transpose(as_tensor_field(F))
            H = dyad(J * G, G)
            dyad_il(-J * G, transpose(G), out=H)
        return H

    def U(self, x) -> np.ndarray:
        """U = ¼κ (θ² − 1 − 2 ln θ) at θ = 1 + x: ¼κ (2x + x² − 2 log1p x), +inf where θ <= 0, MPa."""
        x = np.asarray(x, dtype=float)
        ok = x > -1.0
        t = np.where(ok, x, 0.0)
        return np.where(ok, 0.25 * self.kappa * (t * (2.0 + t) - 2.0 * np.log1p(t)), np.inf)

    def dU(self, x) -> np.ndarray:
        """dU/dθ = ½κ (θ − 1/θ) = ½κ x(2 + x)/(1 + x), MPa (the pressure conjugate to θ)."""
        x = np.asarray(x, dtype=float)
        with np.errstate(all="ignore"):
            return 0.5 * self.kappa * x * (2.0 + x) / (1.0 + x)

    def d2U(self, x) -> np.ndarray:
        """d²U/dθ² = ½κ (1 + 1/θ²), MPa."""
        x = np.asarray(x, dtype=float)
        with np.errstate(all="ignore"):
            return 0.5 * self.kappa * (1.0 + 1.0 / ((1.0 + x) * (1.0 + x)))

    def isochoric_energy(self, F) -> np.ndarray:
        """ψ_iso = ½μ (J^(−2/3) I₁ − 3), +inf where J <= 0, MPa."""
        F = as_tensor_field(F)
        J = det(F)
        ok = J > 0.0
        I1 = np.einsum("ij...,ij...->...", F, F)
        scale = np.where(ok, np.abs(J), 1.0) ** (-2.0 / 3.0)
        return np.where(ok, 0.5 * self.mu * (scale * I1 - 3.0), np.inf)

    def _isochoric_parts(self, F):
        """(F, F⁻ᵀ, I₁ = tr C, μ J^(−2/3)) shared by the isochoric stress and tangent."""
        F = as_tensor_field(F)
        with np.errstate(all="ignore"):
            G, J = inv_transpose(F)
            return F, G, np.einsum("ij...,ij...->...", F, F), self.mu * J ** (-2.0 / 3.0)

    def isochoric_stress(self, F) -> np.ndarray:
        """P_iso = μ J^(−2/3) (F − I₁/3 F⁻ᵀ), shape (3,3,*batch), MPa."""
        F, G, I1, a = self._isochoric_parts(F)
        with np.errstate(all="ignore"):
            return a * (F - (I1 / 3.0) * G)

    def isochoric_tangent(self, F) -> np.ndarray:
        """A_iso (see the class docstring), shape (3,3,3,3,*batch), MPa."""
        F, G, I1, a = self._isochoric_parts(F)
        with np.errstate(all="ignore"):
            A = dyad(-(2.0 / 3.0) * a * F, G)
            dyad(-(2.0 / 3.0) * a * G, F, out=A)
            dyad((2.0 / 9.0) * a * I1 * G, G, out=A)
            dyad_il((a * I1 / 3.0) * G, transpose(G), out=A)
            _add_identity_ik_jl(A, a)
        return A

    # the one-field law (θ = J pointwise): OneFieldSplit


@dataclass(frozen=True)
class SplitLinear(LinearElastic):
    """Small-strain elasticity split into deviatoric and volumetric parts (the B-bar method).

    With ε = sym(F − I), e = tr ε, κ = λ + 2μ/3:
    - ψ_iso = μ dev ε : dev ε,   P_iso = 2μ dev ε,
      A_iso = μ(δ_ik δ_JL + δ_iL δ_Jk) − ⅔μ δ_iJ δ_kL
    - volume change v(F) = tr ε, ∂v/∂F = I, ∂²v = 0
    - U(x) = ½κ x² (x = θ − 1, the projected volume change)
    The sum is exactly :class:`LinearElastic` (μ ε:ε + ½λ e²), whose energy/stress/tangent this
    class inherits.
    """

    name: ClassVar[str] = "linear-split"
    theta_min: ClassVar[float] = -np.inf

    @property
    def kappa(self) -> float:
        return self.bulk_modulus

    def volume(self, F: np.ndarray) -> np.ndarray:
        F = as_tensor_field(F)
        return (F[0, 0] - 1.0) + (F[1, 1] - 1.0) + (F[2, 2] - 1.0)

    def volume_gradient(self, F: np.ndarray) -> np.ndarray:
        F = as_tensor_field(F)
        out = np.zeros_like(F)
        for i in range(3):
            out[i, i] = 1.0
        return out

    def volume_hessian(self, F: np.ndarray) -> None:
        """∂²v/∂F∂F = 0 (None: the mixed body skips the term)."""
        return None

    def U(self, x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        return 0.5 * self.kappa * x * x

    def dU(self, x) -> np.ndarray:
        return self.kappa * np.asarray(x, dtype=float)

    def d2U(self, x) -> np.ndarray:
        return np.full(np.shape(x), self.kappa)

    def _deviator(self, F: np.ndarray) -> np.ndarray:
        eps = self._strain(as_tensor_field(F))
        tr = (eps[0, 0] + eps[1, 1] + eps[2, 2]) / 3.0
        for i in range(3):
            eps[i, i] -= tr
        return eps

    def isochoric_energy(self, F) -> np.ndarray:
        d = self._deviator(F)
        return self.mu * np.einsum("ij...,ij...->...", d, d)

    def isochoric_stress(self, F) -> np.ndarray:
        return 2.0 * self.mu * self._deviator(F)

    def isochoric_tangent(self, F) -> np.ndarray:
        F = as_tensor_field(F)
        I = np.eye(3)
        C = (self.mu * (np.einsum("ik,jl->ijkl", I, I) + np.einsum("il,jk->ijkl", I, I))
             - (2.0 * self.mu / 3.0) * np.einsum("ij,kl->ijkl", I, I))
        batch = F.shape[2:]
        return np.broadcast_to(C.reshape(C.shape + (1,) * len(batch)), C.shape + batch).copy()
