"""Isochoric energies of the invariants Ī₁ = tr C̄, Ī₂ = ½((tr C̄)² − tr C̄²), C̄ = J^(−2/3) C.

A model gives W(x₁, x₂) with x₁ = Ī₁ − 3, x₂ = Ī₂ − 3 and its derivatives W₁ = ∂W/∂Ī₁,
W₂ = ∂W/∂Ī₂, W₁₁, W₁₂, W₂₂ (MPa). With I₁ = F:F, C = FᵀF, b = FFᵀ, I₂ = ½(I₁² − C:C),
G = F⁻ᵀ, a = J^(−2/3), D = 2(I₁F − FC) = ∂I₂/∂F:

    ∂Ī₁/∂F = d₁ = a (2F − ⅔ I₁ G),       ∂Ī₂/∂F = d₂ = a² (D − (4/3) I₂ G)
    P_iso  = W₁ d₁ + W₂ d₂
    A_iso  = W₁₁ d₁⊗d₁ + W₁₂ (d₁⊗d₂ + d₂⊗d₁) + W₂₂ d₂⊗d₂
           + W₁ a [2 δ_ik δ_JL − (4/3)(F⊗G + G⊗F) + (4/9) I₁ G⊗G + ⅔ I₁ G_iL G_kJ]
           + W₂ a² [2(2 F⊗F + I₁ δ_ik δ_JL − δ_ik C_JL − F_iL F_kJ − b_ik δ_JL)
                    − (4/3)(G⊗D + D⊗G) + I₂ ((16/9) G⊗G + (4/3) G_iL G_kJ)]

(the second derivatives of Ī₁, Ī₂ from ∂a/∂F = −⅔ a G and ∂G_iJ/∂F_kL = −G_iL G_kJ). μ0 = 2(W₁ + W₂)
at C̄ = I. ``tangent_terms`` returns A (with the volumetric part of vlab.materials.isochoric) as
the outer products of vlab.materials.structure: the dyads gathered on the basis {F, G, D},
Σ_a X_a ⊗ (Σ_b M_ab X_b), so two (three with Ī₂) dyads, two crosses and two krons per point;
the numpy kernel pulls them back without forming the 81-entry tangent. ``tangent_forms`` gives
the same tangent as a short sum of the compiled kernel's isotropic forms (vlab.fe.compiled).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.isochoric import IsochoricVolumetric
from vlab.materials.structure import IsotropicTangent, TangentTerms
from vlab.tensor import as_tensor_field, dot, inv_transpose, transpose

__all__ = ["InvariantModel"]


@dataclass(frozen=True, kw_only=True)
class InvariantModel(IsochoricVolumetric):
    """ψ_iso = W(Ī₁ − 3, Ī₂ − 3); subclasses define ``W`` and ``mu0``."""

    uses_I2: ClassVar[bool] = False

    def W(self, x1: np.ndarray, x2: np.ndarray) -> tuple:  # pragma: no cover - abstract
        """(W, W₁, W₂, W₁₁, W₁₂, W₂₂) at x₁ = Ī₁ − 3, x₂ = Ī₂ − 3, MPa (scalars or fields)."""
        raise NotImplementedError

    def _kinematics(self, F):
        """J, a = J^(−2/3), G, I₁, x₁, and (C, b, D, I₂, x₂) when the model uses Ī₂."""
        with np.errstate(all="ignore"):
            G, J = inv_transpose(F)
            a = np.where(J > 0.0, np.abs(J), np.nan) ** (-2.0 / 3.0)
            I1 = np.einsum("ij...,ij...->...", F, F)
            k = {"J": J, "a": a, "G": G, "I1": I1, "x1": a * I1 - 3.0, "x2": 0.0}
            if self.uses_I2:
                C = dot(transpose(F), F)
                I2 = 0.5 * (I1 * I1 - np.einsum("ij...,ij...->...", C, C))
                k.update(C=C, b=dot(F, transpose(F)), I2=I2, D=2.0 * (I1 * F - dot(F, C)),
                         x2=a * a * I2 - 3.0)
        return k

    def isochoric_energy(self, F) -> np.ndarray:
        """ψ_iso = W(Ī₁ − 3, Ī₂ − 3), +inf where J <= 0 or W is not finite (locking), MPa."""
        k = self._kinematics(as_tensor_field(F))
        with np.errstate(all="ignore"):
            psi = np.asarray(self.W(k["x1"], k["x2"])[0] + 0.0 * k["x1"], dtype=float)
        return np.where(np.isfinite(psi) & (k["J"] > 0.0), psi, np.inf)

    def isochoric_stress(self, F) -> np.ndarray:
        """P_iso = W₁ d₁ + W₂ d₂, shape (3,3,*batch), MPa."""
        F = as_tensor_field(F)
        k = self._kinematics(F)
        with np.errstate(all="ignore"):
            _, W1, W2, *_ = self.W(k["x1"], k["x2"])
            P = W1 * k["a"] * (2.0 * F - (2.0 / 3.0) * k["I1"] * k["G"])
            if self.uses_I2:
                P = P + W2 * k["a"] ** 2 * (k["D"] - (4.0 / 3.0) * k["I2"] * k["G"])
        return P

    def isochoric_tangent(self, F) -> np.ndarray:
        """A_iso (module docstring), shape (3,3,3,3,*batch), MPa."""
        with np.errstate(all="ignore"):
            return self.tangent_terms(F, volumetric=False).full()

    def tangent(self, F) -> np.ndarray:
        """A = A_iso + the volumetric terms, shape (3,3,3,3,*batch), MPa."""
        with np.errstate(all="ignore"):
            return self.tangent_terms(F).full()

    def tangent_terms(self, F, volumetric: bool = True) -> TangentTerms:
        """A as dyads on the basis {F, G(, D)}, crosses G_iL G_kJ, F_iL F_kJ and δ-krons."""
        F = as_tensor_field(F)
        return self._terms(F, *self._coefficients(F, volumetric))

    def tangent_forms(self, F) -> list[IsotropicTangent]:
        """A as a sum of the compiled kernel's isotropic forms (vlab.fe.compiled): the dyads
        Σ_ab M_ab X_a ⊗ X_b diagonalised per point (M symmetric: Σ_c m_c Z_c ⊗ Z_c,
        Z_c = Σ_a V_ac X_a), the δ-krons carried by the first, then one form per cross
        (β G_iL G_kJ, and −2W₂a² F_iL F_kJ with Ī₂): 3 kernel passes, 5 with Ī₂."""
        F = as_tensor_field(F)
        k, basis, M, c_GG, s, W2 = self._coefficients(F, True)
        batch = F.shape[2:]
        n = len(basis)
        with np.errstate(all="ignore"):
            Mf = np.empty(batch + (n, n))
            for r in range(n):
                for q in range(n):
                    Mf[..., r, q] = M[r][q]
            m, V = np.linalg.eigh(Mf)
            eye = np.eye(3).reshape((3, 3) + (1,) * len(batch))
            S, B = s * eye + np.zeros_like(F), None
            if self.uses_I2:
                w = 2.0 * W2 * k["a"] ** 2
                S, B = S - w * k["C"], -w * k["b"] + np.zeros_like(F)
            forms = []
            for c in range(n):
                Z = sum(V[..., a, c] * basis[a] for a in range(n))
                forms.append(IsotropicTangent(Z, m[..., c], 0.0, 0.0, S if c == 0 else None,
                                              B if c == 0 else None))
            forms.append(IsotropicTangent(k["G"], 0.0, c_GG + np.zeros(batch), 0.0, None, None))
            if self.uses_I2:
                forms.append(IsotropicTangent(F, 0.0, -w + np.zeros(batch), 0.0, None, None))
        return forms

    def _coefficients(self, F, volumetric: bool):
        """(kinematics, basis {F, G(, D)}, dyad coefficients M_ab, cross coefficient of
        G_iL G_kJ, δ_ik δ_JL coefficient, W₂) of the tangent (module docstring)."""
        k = self._kinematics(F)
        with np.errstate(all="ignore"):
            _, W1, W2, W11, W12, W22 = self.W(k["x1"], k["x2"])
            a, I1, G = k["a"], k["I1"], k["G"]
            basis = [F, G] + ([k["D"]] if self.uses_I2 else [])
            n = len(basis)
            d1 = [2.0 * a, -(2.0 / 3.0) * a * I1] + [0.0] * (n - 2)
            M = [[W11 * d1[r] * d1[s] for s in range(n)] for r in range(n)]
            M[0][1] = M[0][1] - (4.0 / 3.0) * W1 * a
            M[1][0] = M[1][0] - (4.0 / 3.0) * W1 * a
            M[1][1] = M[1][1] + (4.0 / 9.0) * W1 * a * I1
            c_GG = (2.0 / 3.0) * W1 * a * I1
            s = 2.0 * W1 * a
            if self.uses_I2:
                a2, I2 = a * a, k["I2"]
                d2 = [0.0, -(4.0 / 3.0) * a2 * I2, a2]
                for r in range(3):
                    for q in range(3):
                        M[r][q] = M[r][q] + W12 * (d1[r] * d2[q] + d2[r] * d1[q]) + W22 * d2[r] * d2[q]
                M[0][0] = M[0][0] + 4.0 * W2 * a2
                M[1][2] = M[1][2] - (4.0 / 3.0) * W2 * a2
                M[2][1] = M[2][1] - (4.0 / 3.0) * W2 * a2
                M[1][1] = M[1][1] + (16.0 / 9.0) * W2 * a2 * I2
                c_GG = c_GG + (4.0 / 3.0) * W2 * a2 * I2
                s = s + 2.0 * W2 * a2 * I1
            if volumetric:
                x, J = self.volume(F), k["J"]
                M[1][1] = M[1][1] + J * J * self.d2U(x) + J * self.dU(x)
                c_GG = c_GG - J * self.dU(x)
        return k, basis, M, c_GG, s, W2

    def _terms(self, F, k, basis, M, c_GG, s, W2) -> TangentTerms:
        """Assemble the TangentTerms of ``tangent_terms`` from its coefficient fields."""
        batch = F.shape[2:]
        eye = np.eye(3).reshape((3, 3) + (1,) * len(batch))
        dyads = [(X, sum(M[r][q] * basis[q] for q in range(len(basis))) + np.zeros_like(F))
                 for r, X in enumerate(basis)]
        cross = [((c_GG + np.zeros(batch), k["G"]), k["G"])]
        kron = [(1.0, s * eye + np.zeros_like(F))]
        if self.uses_I2:
            w = 2.0 * W2 * k["a"] ** 2
            cross.append(((-w + np.zeros(batch), F), F))
            kron = [(1.0, s * eye - w * k["C"]), (-w * k["b"], 1.0)]
        return TangentTerms(batch, kron=kron, dyad=dyads, cross=cross)
