"""Sparse direct solves for the Newton systems K_ff Δu = -r.

Two backends, chosen by measurement (benchmarks/RESULTS.md) and by what is installed:

- ``pardiso`` (optional extra ``vlab[fast]``: pypardiso + the mkl wheel): MKL PARDISO sparse
  Cholesky on the upper triangle, METIS ordering, the symbolic analysis done once per sparsity
  pattern and reused by every later tangent; a non-positive-definite tangent switches that
  pattern to Bunch–Kaufman LDLᵀ, whose inertia is reported. About 7× faster than SuperLU on a
  14,000-DOF hexahedral block.
- ``superlu`` (scipy, always installed, the fallback): SuperLU in symmetric mode. With a
  minimum-degree ordering on A + Aᵀ and no partial pivoting it behaves like an LDLᵀ factorization
  of the symmetric tangents assembled here (U = D Lᵀ, so the signs of diag U give the inertia); if
  a zero pivot appears the factorization is retried with threshold pivoting.

``factorize`` uses the preferred available backend, or the one the installed settings name
(vlab.settings: ``VLAB_LINEAR_SOLVER`` = auto | pardiso | superlu, or ``use_solver``). Every factorization
carries ``negative_pivots`` (count of negative eigenvalues of K_ff, None if unknown), which is
what stability detection needs.

The PARDISO analysis is cached per sparsity pattern (the last few patterns seen), so every
Newton iteration on the same mesh and grips pays only for the numerical factorization.
"""

from __future__ import annotations

import dataclasses
import logging
from functools import cached_property

import numpy as np
import scipy
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from vlab import settings
from vlab.fe import pardiso
from vlab.fe.timers import LINEAR_SOLVE, timed

log = logging.getLogger(__name__)

BACKENDS = ("pardiso", "superlu")
_PATTERNS_KEPT = 4


class SingularSystem(RuntimeError):
    """The tangent has no usable factorization (rigid-body mode or collapsed element)."""


def available_solvers() -> dict[str, str | None]:
    """Each backend with its version string, or None if it is not installed."""
    return {"pardiso": pardiso.version() if pardiso.library() is not None else None,
            "superlu": f"scipy {scipy.__version__}"}


def use_solver(name: str) -> None:
    """Select ``auto`` (fastest installed), ``pardiso`` or ``superlu`` for later factorizations."""
    if name not in ("auto",) + BACKENDS:
        raise ValueError(f"linear solver must be one of auto, {', '.join(BACKENDS)}; got {name!r}")
    if name == "pardiso" and pardiso.library() is None:
        raise ValueError("linear solver 'pardiso' is not installed (pip install 'vlab[fast]')")
    settings.use(dataclasses.replace(settings.current(), linear_solver=name))


def solver_in_use() -> str:
    name = settings.current().linear_solver
    if name == "superlu" or pardiso.library() is None:
        if name == "pardiso":
            log.warning("VLAB_LINEAR_SOLVER=pardiso but PARDISO is not installed; using SuperLU")
        return "superlu"
    return "pardiso"


class Factorization:
    """A factorized symmetric sparse matrix; ``solve`` applies its inverse."""

    backend = "abstract"
    negative_pivots: int | None = None
    cholesky: bool = False  # True: a Cholesky LLᵀ, so the matrix is positive definite
    pivots: np.ndarray | None = None  # diag D of an unpivoted LDLᵀ, where the backend gives it

    def solve(self, b: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    norm_inf: float = np.inf  # ‖K‖∞, for the conditioning check
    norm_bound: float = np.inf  # a cheap upper bound of ‖K‖∞ (the exact one is then needed rarely)

    def _checked(self, x: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Reject non-finite solutions and those proving κ∞(K) ≥ ‖x‖‖K‖/‖b‖ > CONDITION_LIMIT
        (a tiny Cholesky pivot on a singular matrix is backward stable yet meaningless)."""
        if not np.all(np.isfinite(x)):
            raise SingularSystem("the solve produced non-finite values (singular tangent)")
        b_norm = np.max(np.abs(b), initial=0.0)
        limit, x_norm = CONDITION_LIMIT * b_norm, np.max(np.abs(x), initial=0.0)
        if b_norm > 0 and x_norm * self.norm_bound > limit and x_norm * self.norm_inf > limit:
            raise SingularSystem(f"the tangent is numerically singular (condition number above "
                                 f"{CONDITION_LIMIT:.0e})")
        return x


def backward_error(K: sp.spmatrix, x: np.ndarray, b: np.ndarray) -> float:
    """Norm-wise backward error ‖Kx − b‖∞ / (‖K‖∞ ‖x‖∞ + ‖b‖∞): a backward-stable solve gives
    O(machine ε) whatever the conditioning; a tiny pivot without pivoting gives O(1)."""
    norm_K = float(abs(K).sum(axis=1).max())
    denominator = norm_K * np.max(np.abs(x), initial=0.0) + np.max(np.abs(b), initial=0.0)
    return float(np.max(np.abs(K @ x - b), initial=0.0) / max(denominator, 1e-300))


BACKWARD_ERROR_LIMIT = 1e-8
CONDITION_LIMIT = 1e14


def _norm_inf(K: sp.spmatrix) -> float:
    """max_i Σ_j |K_ij| by row segments of the CSR data (no |K| matrix is formed)."""
    K = K if sp.isspmatrix_csr(K) else sp.csr_matrix(K)
    starts = K.indptr[:-1][K.indptr[:-1] < K.indptr[1:]]  # rows with entries
    return float(np.add.reduceat(np.abs(K.data), starts).max()) if len(starts) else 0.0


class SuperLUFactorization(Factorization):
    backend = "superlu"

    def __init__(self, K: sp.spmatrix):
        self._K = sp.csc_matrix(K)
        self.shape = self._K.shape
        self.norm_inf = _norm_inf(self._K)
        try:
            self._lu = spla.splu(self._K, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                 options={"SymmetricMode": True})
        except RuntimeError:
            self._pivoted()
        symmetric = np.array_equal(self._lu.perm_r, self._lu.perm_c)
        self.negative_pivots = int(np.sum(self._lu.U.diagonal() < 0.0)) if symmetric else None

    @property
    def pivots(self) -> np.ndarray | None:
        """diag D of P K Pᵀ = L D Lᵀ (symmetric mode, no pivoting), else None."""
        if self._pivoting or not np.array_equal(self._lu.perm_r, self._lu.perm_c):
            return None
        return self._lu.U.diagonal()

    def _pivoted(self) -> None:
        """Refactorize with threshold partial pivoting (stable for indefinite matrices)."""
        try:
            self._lu = spla.splu(self._K)
        except RuntimeError as exc:
            raise SingularSystem(f"sparse factorization failed: {exc}") from exc
        self._pivoting = True

    _pivoting = False

    @timed(LINEAR_SOLVE)
    def solve(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, dtype=float)
        x = self._lu.solve(b)
        if not self._pivoting and not (np.all(np.isfinite(x)) and
                                       backward_error(self._K, x, b) <= BACKWARD_ERROR_LIMIT):
            log.debug("symmetric-mode SuperLU met a tiny pivot; refactorizing with pivoting")
            self._pivoted()
            x = self._lu.solve(b)
        x = self._checked(x, b)
        if backward_error(self._K, x, b) > BACKWARD_ERROR_LIMIT:
            raise SingularSystem("the tangent is numerically singular (inaccurate solve)")
        return x


class PardisoFactorization(Factorization):
    """A numerical factor held in one slot of a shared PARDISO pattern.

    If later factorizations took the slot over, the factor is recomputed from the kept values
    (correct, only slower; logged at debug level)."""

    backend = "pardiso"

    def __init__(self, pattern: pardiso.PardisoPattern, K: sp.csr_matrix):
        self._pattern = pattern
        self._values = pattern.upper_values(K)
        self.shape = K.shape
        # ‖K‖∞ ≤ max|K_ij| · (most entries in a row): 1 pass over half the values, not |K|
        widest = int(np.max(np.diff(K.indptr), initial=0))
        self.norm_bound = widest * max(float(self._values.max(initial=0.0)),
                                       -float(self._values.min(initial=0.0)))
        self._slot = self._factor()

    @cached_property
    def norm_inf(self) -> float:
        return _norm_inf(self._full_matrix())

    @property
    def cholesky(self) -> bool:
        """True if this factor is a Cholesky LLᵀ (so K_ff is positive definite)."""
        return self._mtype == pardiso.SPD

    def _factor(self) -> int:
        try:
            slot = self._pattern.factor_into_slot(self, self._values)
        except pardiso.PardisoError as exc:
            raise SingularSystem(f"sparse factorization failed: {exc}") from exc
        self.negative_pivots = self._pattern.negative_pivots
        self._mtype = self._pattern.handle.mtype
        return slot

    @timed(LINEAR_SOLVE)
    def solve(self, b: np.ndarray) -> np.ndarray:
        if self._pattern.owner[self._slot] is not self:
            log.debug("PARDISO factor slot reused since; refactorizing")
            self._slot = self._factor()
        b = np.asarray(b, dtype=float)
        try:
            x = self._pattern.solve(self._slot, self._values, b)
        except pardiso.PardisoError as exc:
            raise SingularSystem(f"sparse solve failed: {exc}") from exc
        x = self._checked(x, b)
        if self._pattern.handle.mtype == pardiso.INDEFINITE:
            # Pivot perturbation hides exact singularity: check the backward error instead.
            if backward_error(self._full_matrix(), x, b) > BACKWARD_ERROR_LIMIT:
                raise SingularSystem("the tangent is singular (perturbed pivots, solve inaccurate)")
        return x

    def _full_matrix(self) -> sp.csr_matrix:
        p = self._pattern
        U = sp.csr_matrix((self._values, p.ja - 1, p.ia - 1), shape=(p.n, p.n))
        return U + sp.triu(U, k=1).T


class _PatternCache:
    """The PARDISO patterns of the last few sparsity patterns seen, most recent last.

    A pattern is recognised by comparing index arrays (about 1 ms for a million entries, against
    hundreds of milliseconds for an analysis), so any caller benefits, not only ``Partition``."""

    def __init__(self):
        self._entries: list[tuple[np.ndarray, np.ndarray, pardiso.PardisoPattern]] = []

    def get(self, K: sp.csr_matrix) -> pardiso.PardisoPattern:
        k = self._find(K)
        if k is not None:
            self._entries.append(self._entries.pop(k))
            return self._entries[-1][2]
        pattern = pardiso.PardisoPattern(K)
        self._entries.append((K.indptr.copy(), K.indices.copy(), pattern))
        del self._entries[:-_PATTERNS_KEPT]
        return pattern

    def _find(self, K: sp.csr_matrix) -> int | None:
        for k, (indptr, indices, _) in enumerate(self._entries):
            if (len(indices) == len(K.indices) and np.array_equal(indptr, K.indptr)
                    and np.array_equal(indices, K.indices)):
                return k
        return None


_patterns = _PatternCache()


@timed(LINEAR_SOLVE)
def factorization_cost(K: sp.spmatrix) -> "pardiso.FactorCost | None":
    """What one factorization of K's pattern would cost with PARDISO, from its analysis (made on
    a pattern of its own and released: K may stand for a larger matrix, vlab.pipeline.solve's node
    graph); None without PARDISO or for a pattern it cannot take."""
    if solver_in_use() != "pardiso" or K.shape[0] == 0:
        return None
    K = _sorted_csr(K)
    try:
        pattern = pardiso.PardisoPattern(K)
        return pattern.predicted_cost(pattern.upper_values(K))
    except (ValueError, pardiso.PardisoError) as exc:
        log.debug("no PARDISO analysis of this pattern: %s", exc)
        return None


def _sorted_csr(K: sp.spmatrix) -> sp.csr_matrix:
    K = K if sp.issparse(K) and K.format == "csr" else sp.csr_matrix(K)
    return K if K.has_sorted_indices else K.sorted_indices()


class EmptyFactorization(Factorization):
    """The 0 × 0 system of a test whose grips prescribe every DOF: nothing to solve."""

    backend = "none"
    negative_pivots = 0

    def solve(self, b: np.ndarray) -> np.ndarray:
        return np.zeros(0)


@timed(LINEAR_SOLVE)
def factorize(K: sp.spmatrix) -> Factorization:
    """Factorize a symmetric sparse matrix with the backend in use."""
    if K.shape[0] == 0:
        return EmptyFactorization()
    if solver_in_use() == "pardiso":
        K = _sorted_csr(K)
        try:
            pattern = _patterns.get(K)
        except ValueError as exc:  # a pattern PARDISO cannot take: SuperLU can
            log.debug("%s; using SuperLU", exc)
            return SuperLUFactorization(K)
        return PardisoFactorization(pattern, K)
    return SuperLUFactorization(K)
