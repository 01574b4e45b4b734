"""A hyperelastic body on a discrete space: energy, internal force and tangent at a state u.

Everything here is evaluated on all quadrature points at once; a trial state whose deformation
gradient has J = det F <= J_COLLAPSE at any quadrature point is inadmissible (its energy is +inf),
which is how the line search keeps elements from inverting. The floor is not zero because some
models have spurious equilibria at J -> 0: StVK's P = F S vanishes as the cross-section collapses
to a line (P22 = t S22 -> 0 as t -> 0), so Newton can "converge" to a degenerate state that is
garbage, not physics. No solid in a lab test reaches a volume ratio of 1e-4.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from vlab import jit, settings as installed
from vlab.fe import compiled
from vlab.fe.assembly import (SparsityPattern, element_forces, element_stiffness, scatter_vector,
                              upper_element_stiffness)
from vlab.fe.body import BodyDefaults
from vlab.fe.space import DisplacementSpace
from vlab.fe.timers import ASSEMBLY, timed
from vlab.tensor import det

J_COLLAPSE = 1e-4  # smallest admissible volume ratio det F


@dataclass(frozen=True)
class Evaluation:
    """A state u with its deformation gradient (d,d,e,q), energy W (mJ) and force f_int (N).

    ``min_J`` is the smallest volume ratio over all quadrature points (in 2D the in-plane area
    ratio det F̄; the plane law keeps the thickness stretch λ₃ > 0 itself); ``worst`` its
    (element, quadrature point) index. An inadmissible state has W = +inf and no force.
    """

    u: np.ndarray
    F: np.ndarray
    W: float
    f_int: np.ndarray | None
    min_J: float
    worst: tuple[int, int]

    constraint = 0.0  # a mixed state's max |Π v(F) − θ| (vlab.fe.mixed.MixedEvaluation); 0: none
    volume_change = None  # a mixed state's θ − 1 (element unknowns the body's ``advance`` moves)

    @property
    def admissible(self) -> bool:
        return self.f_int is not None


class HyperelasticBody(BodyDefaults):
    """Couples a material model to a displacement space through vectorized kernels."""

    def __init__(self, space: DisplacementSpace, material, kernel: str = "auto", settings=None):
        """``kernel``: "auto" (the compiled kernels of vlab.fe.compiled for F, the internal force
        and the tangent where they apply and numba is installed), "numpy" (the vectorized numpy
        kernels only) or "compiled" (required). ``settings`` (vlab.settings.Settings: the kernel
        switch and the assembly threads), passed down by the run; None: the installed ones."""
        if kernel not in ("auto", "numpy", "compiled"):
            raise ValueError(f"kernel must be 'auto', 'numpy' or 'compiled'; got {kernel!r}")
        self.space = space
        self.material = material
        self.pattern = SparsityPattern.build(space.element_nodes, space.dim)
        self._compiled = None
        applies = (space.dim == 3 and space.reference_dN is not None
                   and (material.tangent_terms is not None or material.tangent_forms is not None))
        config = settings if settings is not None else installed.current()
        usable = applies and compiled.available(config)
        if kernel == "compiled" and not usable:
            raise ValueError("the compiled tangent kernel needs numba, a 3D isoparametric "
                             "space and a material with tangent_terms or tangent_forms")
        if kernel != "numpy" and usable:
            self._compiled = compiled.CompiledKernels(space, self.pattern, jit.threads(config))
            self._kernel_version = compiled.kernel_in_use(config)
            self._compiled.prepare()   # set-up once per mesh, like the pattern

    @property
    def tangent_kernel(self) -> str:
        """Which kernel assembles the tangent: 'compiled (numba x.y, t threads)' or 'numpy'."""
        return compiled.kernel_label(self._compiled, self._kernel_version if self._compiled is not None else "")

    def gradient(self, u: np.ndarray) -> np.ndarray:
        """F = I + ∂u/∂X (3,3,e,q) by the kernel ``evaluate`` uses, so bit for bit its F."""
        fast = self._compiled
        return fast.deformation_gradient(u) if fast is not None else self.space.deformation_gradient(u)

    @timed(ASSEMBLY)
    def evaluate(self, u: np.ndarray) -> Evaluation:
        F = self.gradient(u)
        J = det(F)  # closed form: LAPACK's batched det of 3×3 matrices is ~10× slower
        worst = np.unravel_index(int(np.argmin(J)), J.shape)
        min_J = float(J[worst])
        if not min_J > J_COLLAPSE:
            return Evaluation(u, F, np.inf, None, min_J, (int(worst[0]), int(worst[1])))
        W = float(np.sum(self.material.energy(F) * self.space.dx))
        if not np.isfinite(W):
            return Evaluation(u, F, np.inf, None, min_J, (int(worst[0]), int(worst[1])))
        P = self.material.stress(F)
        fast = self._compiled
        f_int = (fast.internal_force(P) if fast is not None
                 else scatter_vector(self.space, element_forces(self.space, P)))
        return Evaluation(u, F, W, f_int, min_J, (int(worst[0]), int(worst[1])))

    @timed(ASSEMBLY)
    def stiffness(self, evaluation: Evaluation) -> sp.csr_matrix:
        """Tangent stiffness K = ∂f_int/∂u at an admissible state, N/mm.

        A model that states its tangent as a sum of outer products (``tangent_terms``) never forms
        the full (3,3,3,3,e,q) tangent: in the isotropic form of the three hyperelastic models
        the compiled kernel (vlab.fe.compiled) assembles it, otherwise it is pulled back term by
        term (vlab.fe.assembly)."""
        forms = self.material.tangent_forms  # capabilities: vlab.materials.capabilities
        if self._compiled is not None and forms is not None:  # a sum of isotropic forms (rubber models)
            return self._compiled.matrix(forms(evaluation.F))
        terms = self.material.tangent_terms
        A = terms(evaluation.F) if terms is not None else self.material.tangent(evaluation.F)
        if self._compiled is not None and (form := A.isotropic()) is not None:
            return self._compiled.matrix(form)
        if terms is not None and self.space.reference_dN is not None:
            return self.pattern.symmetric_matrix(upper_element_stiffness(self.space, A))
        return self.pattern.matrix(element_stiffness(self.space, A))
