"""Mixed (three-field, condensed) hyperelastic body: volumetric locking removed element by element.

Three-field Hu–Washizu functional with a split law ψ = ψ_iso(F) + U(v(F)) (vlab/materials/split.py):

    Π(u, θ, p) = Σ_e ∫_e [ψ_iso(F) + U(θ) + p (v(F) − θ)] dV,      (θ, v: volume changes J − 1)

with θ (the volume ratio) and p (the pressure) discontinuous between elements, each a polynomial
of degree k on an element. Stationarity in p makes θ the element L2 projection of v(F),
θ = Π_e v, and then the energy of u alone is

    W(u) = Σ_e Σ_q [ψ_iso(F_q) + U(θ_q)] dx_q,        θ_q = Σ_r Π_e(q, r) v(F_r),
    Π_e(q, r) = φ(q)ᵀ M_e⁻¹ φ(r) dx_r,   M_e = Σ_q φ(q) φ(q)ᵀ dx_q,

a minimisation problem again (so Newton with the energy line search applies unchanged), with
    f_int:  P_eff = P_iso + p ∂v/∂F,           p = Π_e U'(θ) (the projected pressure, MPa)
    K:      A_eff = A_iso + p ∂²v/∂F∂F   assembled by the usual kernels, plus the condensed
            volumetric block per element  K_vol = gᵀ M⁻¹ H M⁻¹ g,
            g_m,ai = Σ_q φ_m(q) (∂v/∂F)_iJ dN_a,J dx_q,   H = Σ_q U''(θ_q) φ φᵀ dx_q.
(Π_e is self-adjoint in the dx-weighted product, which is why p appears as a projection.)

Newton's iteration carries θ as an unknown of its own (:meth:`MixedHyperelasticBody.advance`):
after a step Δu, θ moves by its linearised update instead of being recomputed from u, and the
residual is the condensed three-field one (``evaluate``). Recomputing θ = Π_e v(F(u)) gives the
same solution, but near ν = ½ it puts κ × O(|∇Δu|²) into the pressure after every step and
Newton crawls (issue 20: Cook's membrane ν = 0.4999 Q1/P0 64², 113 → 38 iterations in 10 steps).
W(u) above stays the line search's merit function.

Elements (θ space of degree k, stable pairs):
  hex order 1: Q1 / P0 — the mean-dilatation element (Nagtegaal–Parks–Rice; Simo–Taylor–Pister)
  hex order 2: Q2 / P1dc — θ linear in (X − X_c) per element (inf-sup stable)
  tet order 2: P2 / P0
P1 tets are refused: F and hence J are already constant per element, so a constant θ per
element is the same constraint count as the displacement model and it would lock just the same.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem

from vlab import jit, settings as installed
from vlab.fe import compiled
from vlab.fe.assembly import SparsityPattern, element_forces, element_stiffness, scatter_vector
from vlab.fe.compiled_mixed import CompiledMixedTangent
from vlab.fe.problem import J_COLLAPSE, Evaluation
from vlab.fe.body import BodyDefaults
from vlab.fe.space import DisplacementSpace
from vlab.tensor import det


class MixedUnsupported(ValueError):
    """The mesh/element has no locking-free mixed pair here (P1 tets)."""


@dataclass(frozen=True)
class MixedEvaluation(Evaluation):
    """An Evaluation with the element volume ratio θ and pressure p = Π_e U'(θ) at each
    quadrature point (e, q), and how far θ is from the projected volume ratio of u.

    ``min_J`` is the smaller of min det F and min θ (both volume ratios)."""

    theta: np.ndarray | None = None
    pressure: np.ndarray | None = None
    constraint: float = 0.0  # max |Π_e v(F) − θ| over the quadrature points (0 when θ is projected)
    volume_change: np.ndarray | None = None  # x = θ − 1 (e, q), kept without the round-off of 1 + x − 1


def theta_degree(space: DisplacementSpace) -> int:
    """Polynomial degree of the discontinuous θ/p space paired with the displacement element."""
    element = space.basis.elem
    if isinstance(element, skfem.ElementHex2):
        return 1
    if isinstance(element, (skfem.ElementHex1, skfem.ElementTetP2)):
        return 0
    raise MixedUnsupported(
        "mesh.formulation = 'mixed' is not available for order-1 tets: F is constant per P1 "
        "tetrahedron, so a constant pressure per element constrains exactly as much as the "
        "displacement model and locks the same; use mesh.order = 2 or mesh.cell = 'hex'")


@dataclass(frozen=True)
class VolumeProjection:
    """The element L2 projection onto the discontinuous θ space, precomputed per mesh.

    ``phi`` (e, q, m): θ basis at the quadrature points (1, and for k = 1 (X − X_c)/h);
    ``Minv`` (e, m, m); ``projector`` Π_e (e, q, r), so that θ = Π_e v."""

    phi: np.ndarray
    Minv: np.ndarray
    projector: np.ndarray

    @classmethod
    def build(cls, space: DisplacementSpace, degree: int) -> "VolumeProjection":
        dx = space.dx                                             # (e, q)
        ones = np.ones_like(dx)[:, :, None]
        if degree == 0:
            phi = ones
        else:
            X = np.asarray(space.basis.mapping.F(space.basis.X))  # (3, e, q) mm
            volume = dx.sum(axis=1)
            centre = np.einsum("ieq,eq->ie", X, dx) / volume
            h = np.cbrt(volume)                                   # scaled for conditioning
            local = (X - centre[:, :, None]) / h[None, :, None]
            phi = np.concatenate([ones, np.moveaxis(local, 0, -1)], axis=2)
        M = np.einsum("eqm,eqn,eq->emn", phi, phi, dx)
        Minv = np.linalg.inv(M)
        projector = np.einsum("eqm,emn,ern,er->eqr", phi, Minv, phi, dx)
        return cls(phi, Minv, projector)

    def __call__(self, values: np.ndarray) -> np.ndarray:
        """Π_e applied to a quadrature field (e, q)."""
        return np.einsum("eqr,er->eq", self.projector, values)


class MixedHyperelasticBody(BodyDefaults):
    """Same interface as :class:`vlab.fe.problem.HyperelasticBody` (evaluate, stiffness,
    space, material, pattern); ``material`` is the split law (also a full one-field Material)."""

    def __init__(self, space: DisplacementSpace, law, three_field: bool = True, kernel: str = "auto",
                 settings=None):
        """``three_field``: Newton carries θ with its linearised update (:meth:`advance`); False:
        θ = Π_e v(F) recomputed at every iterate (Newton on W(u) alone: the same solution,
        4-10× the iterations near ν = ½, kept for comparison). ``kernel``: "auto" (F, the
        internal force and the condensed tangent by the compiled kernels of vlab.fe.compiled and
        vlab.fe.compiled_mixed where numba is available) or "numpy" (the numpy kernels only).
        ``settings`` (vlab.settings.Settings: the kernel switch and the assembly threads), passed
        down by the run; None: the installed ones."""
        if kernel not in ("auto", "numpy"):
            raise ValueError(f"kernel must be 'auto' or 'numpy'; got {kernel!r}")
        if not three_field:
            self.advance = None
        self.space = space
        self.material = law
        self.degree = theta_degree(space)
        self.projection = VolumeProjection.build(space, self.degree)
        self.pattern = SparsityPattern.build(space.element_nodes)
        self._compiled = self._tangent = None
        config = settings if settings is not None else installed.current()
        if kernel == "auto" and space.reference_dN is not None and compiled.available(config):
            self._compiled = compiled.CompiledKernels(space, self.pattern, jit.threads(config))
            self._kernel_version = compiled.kernel_in_use(config)
            self._compiled.prepare()  # set-up once per mesh, like the pattern
            self._tangent = CompiledMixedTangent(self._compiled, self.projection)
            self._tangent.prepare()

    @property
    def tangent_kernel(self) -> str:
        """Which kernel assembles the tangent: 'compiled (numba x.y, t threads)' or 'numpy'."""
        return compiled.kernel_label(self._compiled, self._kernel_version if self._compiled is not None else "")

    def gradient(self, u: np.ndarray) -> np.ndarray:
        """F = I + ∂u/∂X (3,3,e,q), bit for bit the F of ``evaluate``."""
        fast = self._compiled
        return fast.deformation_gradient(u) if fast is not None else self.space.deformation_gradient(u)

    def _forces(self, P: np.ndarray) -> np.ndarray:
        fast = self._compiled
        return fast.internal_force(P) if fast is not None else scatter_vector(self.space, element_forces(self.space, P))

    def evaluate(self, u: np.ndarray, volume_change: np.ndarray | None = None) -> MixedEvaluation:
        """The state (u, θ) with θ − 1 = Π_e v(F) (projected, the default) or a given volume
        change x = θ − 1 (e, q) carried by the Newton iteration (see :meth:`advance`).

        W is the energy of u alone (θ projected: the merit function of the line search); f_int
        is the condensed residual of the three-field equations at (u, θ), p = Π_e U'(θ):
            f̃ = R_u + gᵀ M⁻¹ H M⁻¹ R_θ,   R_u = ∫ (P_iso + p ∂v/∂F) : ∇δu,
            R_θ = ∫ φ (v(F) − θ)   (the volume constraint, M⁻¹R_θ = Π_e v − θ),
        i.e. P_eff = P_iso + p̃ ∂v/∂F with p̃ = Π_e [U'(θ) + U''(θ)(Π_e v − θ)]; at θ = Π_e v it is
        ∂W/∂u."""
        law, dx = self.material, self.space.dx
        F = self.gradient(u)
        J = det(F)
        projected = self.projection(law.volume(F))                # Π_e v, the volume change of u
        x = projected if volume_change is None else volume_change
        ratio = np.minimum(J, np.minimum(1.0 + x, 1.0 + projected)) if np.isfinite(law.theta_min) else J
        worst = np.unravel_index(int(np.argmin(ratio)), ratio.shape)
        worst = (int(worst[0]), int(worst[1]))
        min_J = float(ratio[worst])
        if not min_J > J_COLLAPSE:
            return MixedEvaluation(u, F, np.inf, None, min_J, worst, 1.0 + x, volume_change=x)
        W = float(np.sum((law.isochoric_energy(F) + law.U(projected)) * dx))
        if not np.isfinite(W):
            return MixedEvaluation(u, F, np.inf, None, min_J, worst, 1.0 + x, volume_change=x)
        pressure = self.projection(law.dU(x))
        effective = pressure if volume_change is None else pressure + self.projection(law.d2U(x) * (projected - x))
        P = law.isochoric_stress(F) + effective * law.volume_gradient(F)
        f_int = self._forces(P)
        return MixedEvaluation(u, F, W, f_int, min_J, worst, 1.0 + x, pressure,
                               float(np.max(np.abs(projected - x), initial=0.0)), x)

    def advance(self, evaluation: MixedEvaluation, du: np.ndarray, alpha: float) -> MixedEvaluation:
        """The Newton update of the three-field iteration, u + αΔu and θ + αΔθ with
            Δθ = Π_e (∂v/∂F : ∇Δu) + (Π_e v − θ)
        (the linearised constraint R_θ + ∂R_θ/∂u Δu − M Δθ = 0, solved element by element), so
        that θ follows the linearised volume change instead of the exact one: a Newton step
        changes J by O(|∇Δu|²) (a rotation does), κ ≈ 5000 μ at ν = 0.4999 multiplies that, and
        recomputing p from Π_e v would put it in the pressure and the geometric stiffness."""
        law = self.material
        F = evaluation.F
        grad = self.gradient(du)
        for i in range(3):
            grad[i, i] -= 1.0                                     # ∇Δu (3, 3, e, q)
        rate = np.einsum("iJeq,iJeq->eq", law.volume_gradient(F), grad)
        x = evaluation.volume_change
        step = self.projection(rate) + (self.projection(law.volume(F)) - x)
        return self.evaluate(evaluation.u + alpha * du, x + alpha * step)

    def stiffness(self, evaluation: MixedEvaluation) -> sp.csr_matrix:
        """The condensed tangent at the state (u, θ), N/mm: the Schur complement of the
        three-field Jacobian, K = K_uu(p) + gᵀ M⁻¹ H(θ) M⁻¹ g with p = Π_e U'(θ), so that Newton on
        (u, θ) converges quadratically; at θ = Π_e v(F) it is ∂²W/∂u² (Taylor-tested both ways)."""
        law, space = self.material, self.space
        F, x, p = evaluation.F, evaluation.volume_change, evaluation.pressure
        A = law.isochoric_tangent(F)
        hessian = law.volume_hessian(F)
        V, C = law.volume_gradient(F), self._condensed(law.d2U(x))
        if self._tangent is not None:  # the same sums, compiled (vlab.fe.compiled_mixed)
            return self._tangent.matrix(A, hessian, p, V, C)
        if hessian is not None:
            A += p * hessian
        Ke = element_stiffness(space, A)                          # (i, k, e, a, b)
        Ke += self._volumetric_block(V, C)
        return self.pattern.matrix(Ke)

    def _condensed(self, d2U: np.ndarray) -> np.ndarray:
        """C = M⁻¹ H M⁻¹ per element (e, m, n), H = Σ_q U''(θ_q) φ φᵀ dx_q."""
        phi, Minv, dx = self.projection.phi, self.projection.Minv, self.space.dx
        H = np.einsum("eq,eqm,eqn,eq->emn", d2U, phi, phi, dx)
        return Minv @ H @ Minv

    def _volumetric_block(self, V: np.ndarray, C: np.ndarray) -> np.ndarray:
        """gᵀ C g per element in the (i, k, e, a, b) layout of element_stiffness."""
        phi, dx = self.projection.phi, self.space.dx
        g = np.einsum("eqm,iJeq,eqaJ,eq->emai", phi, V, self.space.dN, dx, optimize=True)
        n_el, m, n_loc, _ = g.shape
        G = g.reshape(n_el, m, 3 * n_loc)
        Kv = np.einsum("emx,emn,eny->exy", G, C, G, optimize=True).reshape(n_el, n_loc, 3, n_loc, 3)
        return Kv.transpose(2, 4, 0, 1, 3)
