"""Is K_ff positive definite, and what is its lowest eigenpair, without a factorization?

Above the direct/iterative crossover (vlab.fe.iterative.choose) a sparse factorization of every
converged state's K_ff is what fills the memory (n^(4/3) fill under nested dissection), so the
stability check there is LOBPCG (Knyazev 2001; scipy.sparse.linalg.lobpcg): a block of
``BLOCK`` vectors X, each iteration a Rayleigh–Ritz step on span{X, M⁻¹R, P} with the residuals
R = K X − X Λ preconditioned by the very AMG hierarchy (M⁻¹ ≈ K⁻¹) that CG uses for the Newton
corrections (vlab.fe.iterative.AMGHierarchy: no second set-up). It converges to the algebraically
smallest eigenvalues λ₁ ≤ λ₂ of K_ff (N/mm). The block starts from

- the previous state's lowest eigenvector (warm start: along a load path the lowest mode changes
  little, so a few iterations suffice) and seeded random vectors (a run repeats bit for bit);
- CG's witness: a direction p with pᵀK p ≤ 0 met during the correction solves. Rayleigh–Ritz never
  rises above the Rayleigh quotient of a start vector, so once p is in the block λ₁ ≤ pᵀKp/pᵀp ≤ 0.

Verdict (the same thresholds as the direct path of vlab.fe.inertia, so both classify alike):
with s = max|K_ii| (N/mm), an eigenvalue counts as zero for |λ| ≤ ZERO_TOL · s, negative for
λ < −ZERO_TOL · s. A Ritz value is a Rayleigh quotient xᵀKx/xᵀx, and λ_min ≤ xᵀKx/xᵀx for every x, so
"negative" is a certificate, not an estimate: it can only be wrong by the round-off of xᵀKx
(≲ √n ε s for a unit x, below 1e-12 s here), five orders below the threshold: no false alarm.
"Positive definite" rests on LOBPCG having found the lowest eigenvalue, which the residual check
supports: each returned pair must satisfy ‖K x − λ x‖ ≤ RESIDUAL_TOL · s (‖x‖ = 1, checked anew
here, not taken from LOBPCG's own history), which places an eigenvalue of K within that distance
of λ (and within ‖r‖²/gap of it); or, where LOBPCG stagnates just above that, ‖r‖ ≤ DECIDED_TOL · s
with |λ| > SIGN_MARGIN ‖r‖, so that the interval [λ − ‖r‖, λ + ‖r‖] holding an eigenvalue excludes
zero. The iterations stop as soon as the pair asked for is there: with ``accurate`` (the
lowest eigenvalue itself is wanted: ``[solver] eigenvalues``, a study, the stability suite) at
RESIDUAL_TOL, else (only the verdict is wanted) as soon as the lowest pair is *decided* by the
second rule, which is the verdict's own acceptance test, so it is not weakened: on a thin shell
(the 50k-DOF sphere octant of benchmarks/kinds_felupe.py with ``solver.linear = "cg-amg"``;
``auto`` now factorizes it, vlab.fe.iterative.decide; λ₁ ≈ 9e-3 max|K_ii|, the first two
eigenvalues 3 % apart) the warm-started pair is decided after one to three calls of
FIRST_ITERATIONS on most levels, while reaching RESIDUAL_TOL took another ~45 iterations of a
call that only ends when the random column, too, converges: 183 of the run's 306 s (profiled,
benchmarks/RESULTS.md). The decided test also keeps a near-degenerate pair honest: two modes
0.3 % apart whose order swaps leave the tracked pair's residual above DECIDED_TOL until the
block has found the lower one (seen on that octant). The recorded
lowest eigenvalue then carries its residual (``Inertia.residual``): it lies within ‖r‖ of an
eigenvalue, and its own error is O(‖r‖² / gap). A pair that does not converge is not trusted: the state is then
vetted by the direct factorization after all (method "ldlt-inertia", with the reason logged),
unless its Rayleigh quotient already certifies a negative eigenvalue.

The counts of the returned Inertia are among the BLOCK lowest eigenvalues: ``negative`` is exact
when it is smaller than BLOCK and a lower bound otherwise; the messages say "negative
eigenvalue(s)" either way.

CG keeps vetting: the path slope and the next predictor solve with the same K_ff right after the
check, and a negative curvature met there (a negative eigenvalue LOBPCG missed) makes the monitor
check that state again with the witness in the block (vlab.checks.monitor).
"""

from __future__ import annotations

import logging
import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from vlab.fe.inertia import ZERO_TOL, Inertia, inertia
from vlab.fe.timers import STABILITY, timed

log = logging.getLogger(__name__)

BLOCK = 2  # a square column buckles equally in two directions: both modes in one block
RESIDUAL_TOL = 1e-7  # ‖K x − λ x‖ / max|K_ii| of an accepted eigenpair
#: scipy's LOBPCG can stagnate just above RESIDUAL_TOL on an ill-conditioned K_ff (a clamped Q1
#: strip, 855 DOFs: 1.2e-6 max|K_ii| in one run of the suite, 5e-8 in another): a pair within
#: DECIDED_TOL whose |λ| exceeds SIGN_MARGIN × its residual is accepted, since an eigenvalue of K
#: lies within ‖r‖ of λ (so its sign is decided) and λ's own error is O(‖r‖² / gap)
DECIDED_TOL = 1e-5
SIGN_MARGIN = 10.0
MAX_ITERATIONS = 100
#: scipy's LOBPCG iterates until every pair of the block meets ``tol``, but the verdict rests on
#: the lowest pair (its residual is checked in ``amg_inertia``). From the warm start that pair
#: meets RESIDUAL_TOL in 4-5 iterations, the random column takes 10-11 (16³ cube, every level),
#: so a first call stops here and is continued only if the lowest pair has not converged (the
#: check took 4.4 s → 3.3 s over the 10 levels of the 24³ cube).
FIRST_ITERATIONS = 5
#: scipy's LOBPCG stagnates when its search directions lose orthogonality (seen at a residual of
#: ~2e-5 max|K_ii| on a clamped Q1 strip in compression, 855 DOFs); a restart from the Ritz
#: vectors reached it resolves that
RESTARTS = 4
METHOD = "lobpcg-amg"


@timed(STABILITY)
def amg_inertia(K: sp.spmatrix, solver, zero_tol: float = ZERO_TOL, accurate: bool = True) -> Inertia:
    """Stability of K (module docstring) with ``solver``'s AMG hierarchy as the preconditioner;
    ``solver`` (an AMGConjugateGradient on K) also serves ``Inertia.solve``. ``accurate`` False:
    stop once the verdict is decided, the lowest eigenvalue then only to its recorded residual."""
    K = sp.csr_matrix(K)
    n = K.shape[0]
    scale = float(np.max(np.abs(K.diagonal()), initial=0.0)) or 1.0
    hierarchy = solver.hierarchy
    X = _start_block(n, hierarchy)
    w, V = _lobpcg(K, X, solver.preconditioner, scale, accurate)
    residuals = np.linalg.norm(K @ V - V * w, axis=0)
    tol = zero_tol * scale
    converged = _decided(float(w[0]), float(residuals[0]), scale)
    if not converged and not w[0] < -tol:
        log.warning("LOBPCG did not converge on K_ff (n = %d, residual %.3g × max|K_ii|); "
                    "vetting this state by a direct factorization", n, residuals[0] / scale)
        return inertia(K, zero_tol)
    hierarchy.eigenvectors = V
    negative, zero = int(np.sum(w < -tol)), int(np.sum(np.abs(w) <= tol))
    return Inertia(negative, zero, n - negative - zero, METHOD, _solve_with(solver),
                   lowest=(float(w[0]), V[:, 0].copy()), residual=float(residuals[0] / scale))


def _solve_with(solver):
    """K⁻¹ b by CG to DIRECT_TOLERANCE, from an optional first guess ``x0``."""
    return lambda b, x0=None: solver.solve(b, x0=x0)


def _start_block(n: int, hierarchy) -> np.ndarray:
    """BLOCK start vectors: the last state's lowest eigenvector (same size) and seeded random
    ones, plus CG's negative-curvature witness as an extra column when there is one. A random
    column stays in the block: from the old modes alone LOBPCG converged (residuals small) to
    the two old, now positive, modes while a new one had gone negative (stvk, clamped block in
    compression, 4³ hexes, stretch 0.6 → 0.7); caught by CG's witness, but not to be relied on."""
    block = min(BLOCK, max(n - 1, 1))
    X = np.random.default_rng(0).standard_normal((n, block))
    warm = hierarchy.eigenvectors
    if warm is not None and warm.shape[0] == n and block > 1:
        X[:, 0] = warm[:, 0]
    witness = hierarchy.witness
    if witness is not None and len(witness) == n:
        X = np.column_stack([X, witness]) if X.shape[1] < n - 1 else X
        hierarchy.witness = None  # used: it certified this K (or a nearby one) only
    return X


def _decided(lowest: float, residual: float, scale: float) -> bool:
    """The verdict's acceptance test of the lowest Ritz pair (module docstring): converged to
    RESIDUAL_TOL, or its sign decided, |λ| > SIGN_MARGIN ‖r‖ with ‖r‖ ≤ DECIDED_TOL (× max|K_ii|)."""
    return residual <= RESIDUAL_TOL * scale or (residual <= DECIDED_TOL * scale
                                                and abs(lowest) > SIGN_MARGIN * residual)


#: Without ``accurate``, LOBPCG runs in calls of FIRST_ITERATIONS (each ends with the test of the
#: lowest pair, while a call of MAX_ITERATIONS only ends when every column meets its ``tol``) up
#: to this many; then as with ``accurate``, by calls of MAX_ITERATIONS (a restart resolves a
#: stagnation), but to the whole block's ``_sign_tolerance`` instead of RESIDUAL_TOL: when the
#: tracked mode is overtaken by another (two modes 3 % apart cross on the sphere octant), the
#: random column has to converge on it, and it then does so to the verdict's accuracy only
SIGN_CALLS = 3


def _lobpcg(K: sp.csr_matrix, X: np.ndarray, M, scale: float, accurate: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The BLOCK smallest Ritz pairs, ascending, eigenvectors normalised to ‖x‖ = 1; iterated
    until the lowest pair meets RESIDUAL_TOL (``accurate``) or is decided (``_decided``)."""
    n = K.shape[0]
    if n <= 5 * X.shape[1] + 1:  # too small for a block method: dense
        w, V = np.linalg.eigh(K.toarray())
        return w[:X.shape[1]], V[:, :X.shape[1]]
    tol = RESIDUAL_TOL * scale
    calls = [FIRST_ITERATIONS] * (1 if accurate else SIGN_CALLS) + [MAX_ITERATIONS] * RESTARTS
    for maxiter in calls:
        with warnings.catch_warnings():  # non-convergence is judged by the residuals, below
            warnings.simplefilter("ignore")
            w, X = spla.lobpcg(K, X, M=M, tol=tol, largest=False, maxiter=maxiter)
        X = X / np.linalg.norm(X, axis=0)
        i = int(np.argmin(w))
        residual = float(np.linalg.norm(K @ X[:, i] - w[i] * X[:, i]))
        if residual <= RESIDUAL_TOL * scale or (not accurate and _decided(float(w[i]), residual, scale)):
            break
        tol = tol if accurate else _sign_tolerance(float(w[i]), scale)
    order = np.argsort(w)
    return w[order], X[:, order]


def _sign_tolerance(lowest: float, scale: float) -> float:
    """The residual at which a pair near ``lowest`` is decided: min(DECIDED_TOL · max|K_ii|,
    |λ| / SIGN_MARGIN), made a little tighter (λ moves as it converges), ≥ RESIDUAL_TOL · max|K_ii|."""
    return max(RESIDUAL_TOL * scale, 0.5 * min(DECIDED_TOL * scale, abs(lowest) / SIGN_MARGIN))
