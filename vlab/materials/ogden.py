"""Ogden (N terms): ψ = Σₚ 2μₚ/αₚ² (λ̄₁^αₚ + λ̄₂^αₚ + λ̄₃^αₚ − 3) + U(J), μ0 = Σₚ μₚ.

μₚ (MPa) and αₚ ≠ 0 (dimensionless), Abaqus' convention; λ̄_A = J^(−1/3) λ_A the isochoric
principal stretches. Written in the principal log strains ε_A = ln λ_A, ē_A = ε_A − ⅓ Σ ε_B
(so λ̄_A = exp ē_A and Σ ē_A = 0), with s_p = Σ_C λ̄_C^αₚ:

    ψ_iso   = Σₚ 2μₚ/αₚ² Σ_A expm1(αₚ ē_A)
    τ_A     = ∂ψ_iso/∂ε_A = Σₚ 2μₚ/αₚ (λ̄_A^αₚ − s_p/3)                      (Kirchhoff, MPa)
    c_AB    = ∂τ_A/∂ε_B  = Σₚ 2μₚ (λ̄_A^αₚ (δ_AB − ⅓) − ⅓ λ̄_B^αₚ + s_p/9)
    g_AB    = (τ_A − τ_B)/(ε_A − ε_B) = Σₚ 2μₚ/αₚ λ̄_B^αₚ expm1(αₚ d)/d,   d = ε_A − ε_B,
              with the limit Σₚ 2μₚ λ̄_B^αₚ (1 + αₚ d/2) for |αₚ d| < 1e-8 (exactly c_AA − c_AB at d = 0)

evaluated as ψ_iso = Σₚ 2μₚ Σ_A ē_A² φ₂(αₚ ē_A) and τ_A = Σₚ 2μₚ (q_A − ⅓ Σ_B q_B), q_A = ē_A φ₁(αₚ ē_A),
with φ₁(x) = expm1(x)/x, φ₂(x) = (eˣ − 1 − x)/x² (Σ ē_A = 0 drops the linear term): the same
formulas, but with no 1/αₚ beside a difference of numbers near 1, so a small |αₚ| loses no digits
(through λ̄^α − s/3 with α = 1e-12 the stress was 2 % off, with α ≤ 1e-15 zero: a false limit
point) and αₚ → 0 tends to Hencky's isochoric energy μₚ Σ ē_A², as it should.

and P_iso, A_iso from vlab.materials.principal (the coalescence-safe assembly: every
difference quotient is evaluated through g and the log quotient, so F = I, equibiaxial states
and stretches equal to 1e−8 lose no digits). The volumetric part U(J) adds, in this form,
τ_A += J U'(J) and c_AB += J U' + J² U''; it is added in the F form of
vlab.materials.isochoric. For the compiled tangent kernel ``tangent_forms`` writes the same
tangent as isotropic forms (vlab.materials.structure.IsotropicTangent): six (compiled, large
batches: vlab.materials.ogden_kernel) or nine α X ⊗ X (numpy: the principal basis diagonalises
it blockwise).

ALPHA_RANGE = (0, 100]: the allowed |αₚ| (αₚ ≠ 0). λ̄^αₚ overflows double precision at
|αₚ| ln λ̄ > 709 (|α| = 1e300 raised OverflowError while the scene was read; 100 keeps λ̄ up to
1e3). No lower bound is needed: ψ and τ are evaluated through expm1 quotients (φ₁ below), which
tend to Hencky's isochoric energy μ Σ ē² as αₚ → 0 without cancellation (the plain quotient lost
every digit: 11 % error on σ₁ − σ₂ at |α| = 1e-12, λ = 1.001). Fitted cards keep
0.05 <= |αₚ| <= 30 (vlab.identify.laws).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.hencky import admissible_part
from vlab.materials.isochoric import IsochoricVolumetric
from vlab.materials import ogden_kernel
from vlab.materials.principal import (PrincipalFrame, principal_coefficients, principal_frame,
                                      principal_stress, principal_tangent)
from vlab.materials.structure import IsotropicTangent
from vlab.tensor import as_tensor_field

__all__ = ["ALPHA_RANGE", "Ogden"]

ALPHA_RANGE = (0.0, 100.0)  # |αₚ|; 0 itself is refused (nonzero)

_LAST: dict = {}  # the last (law, F) -> frame, mask, principal quantities (see Ogden._frame)


def _phi1(x: np.ndarray) -> np.ndarray:
    """φ₁(x) = expm1(x)/x, φ₁(0) = 1 (1 + x/2 below |x| < 1e-8, exact there to round-off)."""
    small = np.abs(x) < 1e-8
    return np.where(small, 1.0 + 0.5 * x, np.expm1(x) / np.where(small, 1.0, x))


_PHI2_TERMS = 1.0 / np.array([float(np.prod(np.arange(1, k + 3))) for k in range(15)])  # 1/(k+2)!


def _phi2(x: np.ndarray) -> np.ndarray:
    """φ₂(x) = (eˣ − 1 − x)/x², φ₂(0) = ½: the series Σ xᵏ/(k+2)! to k = 14 for |x| < ½ (the
    next term < 3e-18 of the sum), else (expm1(x) − x)/x² (cancellation at most 1 digit there)."""
    small = np.abs(x) < 0.5
    series = np.polynomial.polynomial.polyval(np.where(small, x, 0.0), _PHI2_TERMS)
    xs = np.where(small, 1.0, x)
    return np.where(small, series, (np.expm1(xs) - xs) / (xs * xs))


@dataclass(frozen=True, kw_only=True)
class Ogden(IsochoricVolumetric):
    mus: tuple[float, ...]     # μₚ, MPa (card key mu)
    alphas: tuple[float, ...]  # αₚ (card key alpha)

    name: ClassVar[str] = "ogden"

    def __post_init__(self) -> None:
        object.__setattr__(self, "mus", tuple(float(m) for m in self.mus))
        object.__setattr__(self, "alphas", tuple(float(a) for a in self.alphas))
        if len(self.mus) != len(self.alphas) or not self.mus:
            raise ValueError(f"ogden: mu and alpha need the same, nonzero length, got "
                             f"{len(self.mus)} and {len(self.alphas)}")
        if any(a == 0.0 for a in self.alphas):
            raise ValueError(f"ogden: every alpha must be != 0, got {self.alphas}")
        super().__post_init__()

    @property
    def mu0(self) -> float:
        return float(sum(self.mus))

    def principal_iso(self, eps: np.ndarray) -> tuple[np.ndarray, ...]:
        """(ψ_iso, τ_A, c_AB, g_AB) from the principal log strains ε (3,*batch) (module docstring)."""
        e = eps - eps.mean(axis=0)                                   # ē_A
        batch = eps.shape[1:]
        psi, tau = np.zeros(batch), np.zeros(eps.shape)
        c, g = np.zeros((3, 3) + batch), np.zeros((3, 3) + batch)
        d = eps[:, None] - eps[None, :]                              # ε_A − ε_B
        eye = np.eye(3).reshape((3, 3) + (1,) * len(batch))
        for mu, al in zip(self.mus, self.alphas):
            x = al * e
            m = np.expm1(x)                                          # λ̄_A^α − 1
            lam = 1.0 + m                                            # λ̄_A^α
            s = lam.sum(axis=0)
            # ψ and τ from expm1's quotients, not from λ̄^α − 1 and 1/α: exact as α → 0 (Hencky's μ Σ ē²)
            psi += 2.0 * mu * (e * e * _phi2(x)).sum(axis=0)
            q = e * _phi1(x)                                         # m / α
            tau += 2.0 * mu * (q - q.mean(axis=0))
            c += 2.0 * mu * (lam[:, None] * (eye - 1.0 / 3.0) - lam[None, :] / 3.0 + s / 9.0)
            g += 2.0 * mu * lam[None, :] * _phi1(al * d)
        return psi, tau, c, g

    def _frame(self, F):
        """(principal frame, mask J > 0, principal_iso, P_iso or None) of F; the last F's are
        kept, because the solver asks for ψ, P and the tangent of the same F in turn (one entry,
        checked by value, not id). Large batches take the compiled kernel (vlab.materials.
        ogden_kernel: frame, ψ, τ, c, g and P_iso in one pass), small ones numpy's eigh."""
        F = as_tensor_field(F)
        hit = _LAST.get("key")
        if hit is not None and hit[0] == self and hit[1].shape == F.shape and np.array_equal(hit[1], F):
            return _LAST["value"]
        Fa, ok = admissible_part(F)
        module = ogden_kernel.kernels(int(np.prod(F.shape[2:], dtype=int)))
        if module is not None:
            out = ogden_kernel.state(module, Fa, np.array(self.mus), np.array(self.alphas))
            frame = PrincipalFrame(lam=out["lam"], eps=out["eps"], n=out["n"], N=out["N"])
            value = (frame, ok, (out["psi"], out["tau"], out["c"], out["g"]), out["P"])
        else:
            frame = principal_frame(Fa)
            value = (frame, ok, self.principal_iso(frame.eps), None)
        _LAST["key"], _LAST["value"] = (self, F.copy()), value
        return value

    def isochoric_energy(self, F) -> np.ndarray:
        """ψ_iso, +inf where J <= 0, MPa."""
        _, ok, (psi, *_), _ = self._frame(F)
        return np.where(ok, psi, np.inf)

    def isochoric_stress(self, F) -> np.ndarray:
        """P_iso = Σ_A τ_A/λ_A n_A ⊗ N_A, nan where J <= 0, MPa."""
        frame, ok, (_, tau, _, _), P = self._frame(F)
        return np.where(ok, principal_stress(frame, tau) if P is None else P, np.nan)

    def tangent_forms(self, F) -> list[IsotropicTangent]:
        """A (isochoric + volumetric) as nine isotropic forms α X ⊗ X of the compiled kernel: in
        the orthonormal basis M_AB = n_A ⊗ N_B the tangent is block diagonal (vlab.materials.
        principal), the 3×3 block w_AB on M_AA diagonalised per point (3 forms) and each pair
        block [[t1, t2], [t2, t1]] on (M_AB, M_BA) split into a = t1 + t2 on (M_AB + M_BA)/√2
        and b = t1 − t2 on (M_AB − M_BA)/√2 (6 forms). J ≤ 0 is never assembled (the solver
        rejects such states before asking for a tangent)."""
        F = as_tensor_field(F)
        frame, ok, (_, tau, c, g), _ = self._frame(F)
        lam, n, N = frame.lam, frame.n, frame.N
        J = np.prod(lam, axis=0)
        x = self.volume(F)
        tau = tau + J * self.dU(x)
        c = c + J * self.dU(x) + J * J * self.d2U(x)
        w, a, b = principal_coefficients(frame, tau, c, g)
        module = ogden_kernel.kernels(int(np.prod(lam.shape[1:], dtype=int)))
        if module is not None:  # six forms (vlab.materials.ogden_kernel), no per-point eigh of w
            X, alpha, beta, S, B = ogden_kernel.forms(module, n, N, w, 0.5 * (a + b), 0.5 * (a - b))
            return [IsotropicTangent(X[k], alpha[k], beta[k], 0.0, S if k == 0 else None,
                                     B if k == 0 else None) for k in range(6)]
        M = [[np.einsum("i...,J...->iJ...", n[:, A], N[:, B]) for B in range(3)] for A in range(3)]
        Wm = np.moveaxis(w, (0, 1), (-2, -1))
        m, V = np.linalg.eigh(Wm)
        forms = [IsotropicTangent(sum(V[..., A, k] * M[A][A] for A in range(3)), m[..., k], 0.0, 0.0,
                                  None, None) for k in range(3)]
        root = np.sqrt(0.5)
        for A, B in ((0, 1), (0, 2), (1, 2)):
            forms.append(IsotropicTangent(root * (M[A][B] + M[B][A]), a[A, B], 0.0, 0.0, None, None))
            forms.append(IsotropicTangent(root * (M[A][B] - M[B][A]), b[A, B], 0.0, 0.0, None, None))
        return forms

    def isochoric_tangent(self, F) -> np.ndarray:
        """A_iso from (τ, c, g) in the principal frame, nan where J <= 0, MPa."""
        frame, ok, (_, tau, c, g), _ = self._frame(F)
        return np.where(ok, principal_tangent(frame, tau, c, g), np.nan)
