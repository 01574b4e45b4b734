"""Inertia and lowest eigenpair of a symmetric tangent K_ff: is a converged state stable?

A converged equilibrium is stable (a strict local minimum of the total energy W on the free DOFs)
iff K_ff = ∂²W/∂u_f² is positive definite. By Sylvester's law of inertia, a symmetric
factorization P K Pᵀ = L D Lᵀ (L unit lower triangular, D diagonal) has as many negative entries
in D as K has negative eigenvalues. SuperLU in symmetric mode with diagonal pivoting disabled and
the same permutation on rows and columns computes exactly that (its U equals D Lᵀ), so
inertia(K) = signs of diag(U). If SuperLU had to pivot off the diagonal (perm_r ≠ perm_c) the
signs no longer mean anything and the count falls back to a dense symmetric eigensolver (small
systems) or is reported as unknown (None).

(The PyPI package ``qdldl`` exposes the same D through ``Solver(K).factors()``; SuperLU already
ships with scipy, so no extra dependency is needed.)

A pivot whose magnitude is below ``zero_tol`` times the largest diagonal entry of K counts as
zero: a (nearly) singular tangent, e.g. an unrestrained rigid-body mode.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

DENSE_LIMIT = 3000  # largest system whose inertia is counted densely when SuperLU pivoted
ZERO_TOL = 1e-10
DENSE_EIGEN_LIMIT = 100  # above this, Lanczos beats a dense O(n³) eigensolver


@dataclass(frozen=True)
class Inertia:
    """Counts of negative, (numerically) zero and positive eigenvalues of K; ``method`` says how.

    ``negative`` and ``zero`` are None when the inertia could not be determined.
    """

    negative: int | None
    zero: int | None
    positive: int | None
    method: str
    solve: Callable[[np.ndarray], np.ndarray] | None = None  # K⁻¹ from the same factorization
    lowest: tuple[float, np.ndarray] | None = None  # (λ₁, x₁) when the method found it (LOBPCG)
    residual: float | None = None  # ‖K x₁ − λ₁ x₁‖ / max|K_ii| of that pair

    @property
    def key(self) -> str:
        """The method as results.json names it: ldlt-inertia | cholesky | dense-eigenvalues |
        lobpcg-amg | unknown."""
        for prefix, key in (("LDLt", "ldlt-inertia"), ("Cholesky", "cholesky"),
                            ("dense", "dense-eigenvalues"), ("lobpcg", "lobpcg-amg")):
            if self.method.startswith(prefix):
                return key
        return "unknown"

    @property
    def positive_definite(self) -> bool | None:
        if self.negative is None:
            return None
        return self.negative == 0 and self.zero == 0


def inertia(K: sp.spmatrix, zero_tol: float = ZERO_TOL) -> Inertia:
    """Number of negative / zero / positive eigenvalues of the symmetric matrix K."""
    K = sp.csc_matrix(K)
    n = K.shape[0]
    scale = float(np.max(np.abs(K.diagonal()), initial=0.0)) or 1.0
    try:
        lu = spla.splu(K, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})
    except RuntimeError:  # exactly zero pivot: singular
        lu = None
    if lu is not None and np.array_equal(lu.perm_r, lu.perm_c):
        d = lu.U.diagonal()
        if np.all(np.isfinite(d)):
            return _count(d, zero_tol * scale, "LDLt (SuperLU symmetric mode)", lu.solve)
    if n <= DENSE_LIMIT:
        return _count(np.linalg.eigvalsh(K.toarray()), zero_tol * scale, "dense eigenvalues")
    return Inertia(None, None, None, "unknown (SuperLU pivoted, system too large for dense)")


def factorized_inertia(factor, K: sp.spmatrix, zero_tol: float = ZERO_TOL,
                       verify_zero: bool = True, accurate: bool = True) -> Inertia:
    """The inertia of K from the Newton solver's own factorization of K (no second one) when
    that factorization is conclusive, else ``inertia(K)``:

    - a PARDISO Cholesky (LLᵀ) exists only for a positive definite K: no negative eigenvalue.
      A numerically zero eigenvalue (a rigid-body mode the grips leave free) can still slip
      through with a tiny round-off pivot, so two steps of inverse iteration with the factor
      (two solves, no factorization) bound λ_min from above by a Rayleigh quotient: when
      λ_min ≈ 0 the very first step lands on its eigenvector (the gap to λ₂ is ~1e10), so
      a quotient ≤ zero_tol · max|K_ii| means a zero eigenvalue and the count is done anew.
    - SuperLU in symmetric mode without pivoting: the signs of diag U as in ``inertia``.
    - CG + AMG (no factor at all): LOBPCG preconditioned by the same hierarchy (vlab.fe.eigen_amg).
    Everything else (PARDISO's LDLᵀ with perturbed pivots, pivoted LU) is counted anew.

    ``verify_zero=False`` skips the two solves behind a Cholesky: for states along a load path
    whose unloaded K_ff was verified free of zero eigenvalues, where an eigenvalue reaches zero
    only by crossing it (and the crossing shows as a failed Cholesky, i.e. negative pivots).
    ``accurate=False``: only the counts are wanted, so LOBPCG stops once they are decided
    (vlab.fe.eigen_amg; a factorization gives them exactly anyway)."""
    backend = factor.backend
    if backend == "cg-amg":  # no factorization on the iterative path: LOBPCG + the same AMG
        from vlab.fe.eigen_amg import amg_inertia

        return amg_inertia(K, factor, zero_tol, accurate)
    if backend == "pardiso" and factor.cholesky:
        n = K.shape[0]
        if n == 0 or not verify_zero or (_rayleigh_after_inverse_iteration(factor.solve, K)
                                         > zero_tol * (float(np.max(np.abs(K.diagonal()))) or 1.0)):
            return Inertia(0, 0, n, "Cholesky (PARDISO, all pivots positive)", factor.solve)
        return inertia(K, zero_tol)
    pivots = factor.pivots
    if backend == "superlu" and pivots is not None and np.all(np.isfinite(pivots)):
        scale = float(np.max(np.abs(K.diagonal()), initial=0.0)) or 1.0
        return _count(pivots, zero_tol * scale, "LDLt (SuperLU symmetric mode)", factor.solve)
    return inertia(K, zero_tol)


def _rayleigh_after_inverse_iteration(solve, K: sp.spmatrix, steps: int = 2) -> float:
    """xᵀKx / xᵀx after ``steps`` of x ← K⁻¹x from a fixed pseudo-random start (≥ λ_min)."""
    x = np.random.default_rng(0).standard_normal(K.shape[0])
    for _ in range(steps):
        x = solve(x)
        norm = float(np.linalg.norm(x))
        if not np.isfinite(norm) or norm == 0.0:
            return 0.0
        x /= norm
    return float(x @ (K @ x))


def _count(values: np.ndarray, tol: float, method: str, solve=None) -> Inertia:
    zero = int(np.sum(np.abs(values) <= tol))
    negative = int(np.sum(values < -tol))
    return Inertia(negative, zero, len(values) - negative - zero, method, solve)


def lowest_eigenpair(K: sp.spmatrix, negative: int | None = None,
                     solve: Callable[[np.ndarray], np.ndarray] | None = None) -> tuple[float, np.ndarray]:
    """The algebraically smallest eigenvalue of K (N/mm) and its unit eigenvector.

    Shift-invert Lanczos (``eigsh`` with σ): the eigenvalues of (K − σI)⁻¹ largest in magnitude
    belong to the eigenvalues of K nearest σ. With σ just below zero (−1e-8 |K|_diag,max, so that
    a semi-definite K stays factorizable) the k = negative + 2 nearest eigenvalues converge in a
    few Lanczos steps, and the smallest of them is λ_min when all ``negative`` eigenvalues (the
    count from the inertia) are among them; if some are missing (a strongly indefinite K whose
    negative eigenvalues lie further from zero than its lowest positive ones) σ moves below
    −2 max|λ found| and the solve repeats. ``solve`` = K⁻¹ from a factorization already made (the
    inertia's LDLᵀ) lets the first attempt use σ = 0 without factorizing again. Small systems
    use a dense solve.
    """
    K = sp.csc_matrix(K)
    n = K.shape[0]
    if n <= DENSE_EIGEN_LIMIT:
        w, v = np.linalg.eigh(K.toarray())
        return float(w[0]), v[:, 0]
    scale = float(np.max(np.abs(K.diagonal()), initial=1.0))
    expected = negative or 0
    sigma = 0.0 if solve is not None else -1e-8 * scale
    for _ in range(6):
        k = min(n - 1, expected + 2)
        inverse = (spla.LinearOperator(K.shape, matvec=solve, dtype=float)
                   if solve is not None and sigma == 0.0 else None)
        w, v = _shift_invert_lanczos(K, k, sigma, inverse)
        if int(np.sum(w < 0.0)) >= expected:
            break
        sigma = -2.0 * float(np.max(np.abs(w)))
    i = int(np.argmin(w))
    return float(w[i]), v[:, i]


class EigenpairNotFound(RuntimeError):
    """Shift-invert Lanczos did not converge, even with a wider Krylov space."""


LANCZOS_ATTEMPTS = 3


def _shift_invert_lanczos(K: sp.csc_matrix, k: int, sigma: float,
                          inverse: spla.LinearOperator | None) -> tuple[np.ndarray, np.ndarray]:
    """``eigsh`` in shift-invert mode, retried on non-convergence.

    A symmetric specimen has (nearly) repeated eigenvalues: a square column buckles equally in
    two directions, and four far-apart soft wells of a 1D chain give a 4-fold cluster equal to
    machine precision. Lanczos from one start vector then converges to the copies of a cluster
    only through rounding, and with k smaller than the cluster ARPACK can run out of iterations
    (seen with k = 2 on a 4-fold cluster for ~5 % of random start vectors). Each retry asks for
    two more eigenvalues in a Krylov space twice as wide, from another start vector. The start
    vectors are seeded, so a run repeats bit for bit.
    """
    n = K.shape[0]
    ncv = min(n, max(2 * k + 1, 20))
    last = None
    for attempt in range(LANCZOS_ATTEMPTS):
        v0 = np.random.default_rng(attempt).standard_normal(n)
        try:
            return spla.eigsh(K, k=k, sigma=sigma, which="LM", OPinv=inverse, v0=v0, ncv=ncv)
        except spla.ArpackNoConvergence as exc:
            last = exc
            k = min(n - 1, k + 2)
            ncv = min(n, max(2 * ncv, 2 * k + 1))
    raise EigenpairNotFound(f"lowest eigenpair of K_ff (n = {n}): shift-invert Lanczos at σ = {sigma:.3g} "
                            f"did not converge in {LANCZOS_ATTEMPTS} attempts (last: {last})")
