"""Conjugate gradients preconditioned by smoothed-aggregation algebraic multigrid (pyamg).

For large meshes a Newton correction K_ff Δu = -r need not be solved exactly: inexact Newton
keeps its fast local convergence if the linear residual satisfies
    ‖K_ff Δu + r‖ ≤ η ‖r‖,   η = forcing term (see ``forcing_term``),
and CG with an AMG preconditioner reaches that in a few tens of matrix-vector products whatever
the mesh size, without a factorization. Smoothed aggregation needs the near-nullspace of the
elasticity operator: the six rigid-body modes (three translations, three rotations e_a × X) of
the nodes, restricted to the free DOFs.

CG needs K_ff symmetric positive definite. It meets a direction p with pᵀK p ≤ 0 on an
indefinite tangent; that (and non-convergence) raises ``IterativeSolveFailed`` so the caller falls
back to a direct factorization (which also gives the inertia that stability detection needs;
CG cannot count negative eigenvalues, so ``negative_pivots`` is None here).

pyamg is a dependency of vlab; ``available()`` still checks, for installs without it.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from vlab.fe.linsolve import Factorization, SingularSystem

MAX_ITERATIONS = 400
DIRECT_TOLERANCE = 1e-10  # relative residual when the solver stands in for a factorization


class IterativeSolveFailed(SingularSystem):
    """CG met negative curvature (indefinite K_ff) or did not converge."""


def available() -> str | None:
    """pyamg's version if installed, else None."""
    try:
        import pyamg
    except ImportError:
        return None
    return f"pyamg {pyamg.__version__}"


# Free DOFs from which CG + AMG beats the direct solver on one Newton system, measured with
# benchmarks/linear_solvers.py (Neo-Hookean hexahedral blocks at stretch 1.3, 2 shared cores,
# load average 4.5; setup + solve to 1e-8, seconds):
#   free DOFs   1,863  5,915  13,583  44,375  103,455
#   PARDISO      0.02   0.13    0.43    2.40    15.2
#   SuperLU      0.05   0.81    2.48   27.9       -
#   CG + AMG     0.08   0.27    0.89    2.71     5.58
CROSSOVER = {"pardiso": 50_000, "superlu": 5_000}


def choose(requested: str, n_free: int, direct_backend: str) -> str:
    """"direct" or "cg-amg" for ``[solver] linear`` = auto | direct | cg-amg.

    auto: CG + AMG from the measured crossover of the installed direct solver on, if pyamg is
    installed. An explicit "cg-amg" without pyamg raises ValueError naming the setting."""
    if requested == "cg-amg" and available() is None:
        raise ValueError("solver.linear = 'cg-amg' needs pyamg (pip install pyamg)")
    if requested != "auto":
        return requested
    threshold = CROSSOVER.get(direct_backend, CROSSOVER["superlu"])
    return "cg-amg" if n_free >= threshold and available() is not None else "direct"


def rigid_body_modes(X: np.ndarray) -> np.ndarray:
    """(3 n_nodes, 6) with dof = 3·node + component: translations e_a, rotations e_a × (X − X̄), mm."""
    n = len(X)
    B = np.zeros((3 * n, 6))
    for a in range(3):
        B[a::3, a] = 1.0
    x, y, z = (X - X.mean(axis=0)).T
    B[1::3, 3], B[2::3, 3] = -z, y
    B[0::3, 4], B[2::3, 4] = z, -x
    B[0::3, 5], B[1::3, 5] = -y, x
    return B


def forcing_term(relative_residual: float, rtol: float) -> float:
    """η for the next correction: min(1e-2, ‖r‖_rel) early on (superlinear convergence), but no
    tighter than needed to take the residual a decade below rtol in one step, and ≥ 1e-12."""
    return max(min(1e-2, relative_residual), 0.1 * rtol / max(relative_residual, 1e-300), 1e-12)


class AMGConjugateGradient(Factorization):
    """Stands in for a factorization of K_ff: ``solve(b, rtol)`` runs preconditioned CG."""

    backend = "cg-amg"
    negative_pivots = None

    def __init__(self, K: sp.spmatrix, near_nullspace: np.ndarray):
        import pyamg

        self._K = sp.csr_matrix(K)
        self.shape = self._K.shape
        self.iterations: list[int] = []
        self._ml = pyamg.smoothed_aggregation_solver(
            self._K, B=near_nullspace, symmetry="symmetric", max_coarse=300,
            coarse_solver="splu", improve_candidates=None)
        self._M = self._ml.aspreconditioner(cycle="V")

    def solve(self, b: np.ndarray, rtol: float = DIRECT_TOLERANCE) -> np.ndarray:
        """x with ‖K x − b‖ ≤ rtol ‖b‖ (preconditioned CG from x = 0)."""
        b = np.asarray(b, dtype=float)
        b_norm = math.sqrt(float(b @ b))
        x = np.zeros_like(b)
        if b_norm == 0.0:
            return x
        r = b.copy()
        z = self._M @ r
        p = z.copy()
        rz = float(r @ z)
        for k in range(1, MAX_ITERATIONS + 1):
            Kp = self._K @ p
            curvature = float(p @ Kp)
            if not curvature > 0.0:
                raise IterativeSolveFailed(f"CG met negative curvature pᵀKp = {curvature:.3g} "
                                           f"(indefinite tangent) at iteration {k}")
            alpha = rz / curvature
            x += alpha * p
            r -= alpha * Kp
            if math.sqrt(float(r @ r)) <= rtol * b_norm:
                self.iterations.append(k)
                return x
            z = self._M @ r
            rz_new = float(r @ z)
            p *= rz_new / rz
            p += z
            rz = rz_new
        raise IterativeSolveFailed(f"CG did not reach {rtol:.1e} in {MAX_ITERATIONS} iterations")
