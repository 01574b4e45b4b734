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
back to a direct factorization, and p is kept as a witness of indefiniteness. CG cannot count
negative eigenvalues (``negative_pivots`` is None here): on this path the stability check is
LOBPCG preconditioned by the same hierarchy (vlab.fe.eigen_amg).

One ``AMGHierarchy`` serves a whole run: its set-up (aggregation, smoothed prolongators, Galerkin
coarse operators) is reused by later tangents until CG slows down (``REBUILD_FACTOR``).

pyamg is a dependency of vlab; ``available()`` still checks, for installs without it.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np
import scipy.sparse as sp

from vlab import settings
from vlab.fe.blas import serial_openblas
from vlab.fe.linsolve import Factorization, SingularSystem
from vlab.fe.timers import LINEAR_SOLVE, timed

if TYPE_CHECKING:
    from vlab.fe.pardiso import FactorCost

log = logging.getLogger(__name__)

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
#: Whole runs since the Jacobi smoother (SMOOTHER) and the shared hierarchy, benchmarks/cube_scaling.py
#: (10 steps to stretch 1.5, the stability check at every level, quiet machine, seconds):
#:   cube  DOFs     PARDISO + Cholesky check   CG + AMG + LOBPCG check
#:   16³   14,739   2.97, 3.03                 3.16, 3.01
#:   24³   46,875   13.25                      10.7-11.9
#: so PARDISO's crossover moved from 50,000 to 20,000 free DOFs (the iterative path also peaks
#: lower: 317 against 443 MB at 16³)
CROSSOVER = {"pardiso": 20_000, "superlu": 5_000}

#: The DOF count is the crossover of cubes only. What a factorization costs depends on the
#: mesh's shape: nested dissection fills a 3D body as n^(4/3) (flops ∝ n²) but a thin shell, a
#: plate or a sheet like a 2D mesh (flops ∝ n^1.5), while a CG iteration costs the same per
#: stored entry of K in both. So above CROSSOVER, with PARDISO, ``decide`` asks PARDISO's
#: analysis (METIS ordering and symbolic factorization, of the node graph: vlab.pipeline.solve)
#: how many flops one factorization takes per stored entry of K_ff, and stays direct below this
#: ratio. Whole runs, `python benchmarks/linear_path.py` (quiet 2-core machine, load 1.1-1.4;
#: PARDISO threaded, CG + AMG serial), wall s (CPU s), flops per entry from K_ff's own analysis:
#:   mesh (free DOFs)                          flops/nnz   PARDISO + Cholesky   CG + AMG + LOBPCG
#:   sphere octant A 10, H 1, 30 steps (44,520)    2,811   23.4 (45.2)          109.9 (114.7)
#:   plate 60×20×6 h 0.75, 10 steps (60,729)       6,039   15.8 (29.8)           43.2 (45.1)
#:   plate 30×30×10 h 0.9, 10 steps (46,862)       9,016   15.2 (29.0)           24.4 (25.4)
#:   cube 24³, 10 steps (45,622)                  12,112   21.5 (41.6)           21.6 (22.6)
#:   cylinder torsion, 10 steps (49,959)          14,149   53.9 (105.4)          50.2 (53.0)
#: The direct path is the faster in wall time up to ~12,000 and costs no more CPU up to ~9,000;
#: the crossover sits between: direct while the factorization is the cheaper in both
FLOPS_PER_NONZERO = 10_000
#: Beyond this many free DOFs even a shell's factorization costs more per entry (2,811 at 44,520
#: growing as √n), and METIS's ordering alone takes seconds: CG + AMG without asking
ANALYSE_UP_TO = 500_000
#: The factor (two slots of PARDISO's, vlab.fe.pardiso.SLOTS) may take this share of the
#: memory available when the run starts; else CG + AMG, whose memory grows linearly
FACTOR_MEMORY_SHARE = 0.5


@dataclass(frozen=True)
class LinearChoice:
    """The linear path of a run's Newton corrections and stability checks, and why."""

    path: str  # "direct" | "cg-amg"
    reason: str


def choose(requested: str, n_free: int, direct_backend: str, supported: bool = True) -> str:
    """"direct" or "cg-amg" for ``[solver] linear`` by the DOF count alone (``decide``, without
    the factorization's cost: what the size budget uses before the mesh exists)."""
    return decide(requested, n_free, direct_backend, supported).path


def decide(requested: str, n_free: int, direct_backend: str, supported: bool = True,
           cost: Callable[[], "FactorCost | None"] | None = None) -> LinearChoice:
    """The path for ``[solver] linear`` = auto | direct | cg-amg.

    auto: CG + AMG from the measured crossover of the installed direct solver on (or from the
    installed settings' ``iterative_from``), if pyamg is installed; there, with PARDISO and no
    ``iterative_from``, ``cost()`` (PARDISO's analysis of K_ff: vlab.fe.linsolve.factorization_cost)
    keeps the direct path while a factorization costs ≤ FLOPS_PER_NONZERO flops per stored entry
    and its factor fits the memory (the comment above). An explicit "cg-amg" without pyamg
    raises ValueError naming the setting. ``supported`` False (a body CG + AMG does not take:
    see ``supports``) keeps the direct path."""
    if requested == "cg-amg" and available() is None:
        raise ValueError("solver.linear = 'cg-amg' needs pyamg (pip install pyamg)")
    if not supported:
        return LinearChoice("direct", "CG + AMG does not take this body (not 3D displacement DOFs)")
    if requested != "auto":
        return LinearChoice(requested, f"solver.linear = {requested!r}")
    start = settings.current().iterative_from
    threshold = start if start is not None else CROSSOVER.get(direct_backend, CROSSOVER["superlu"])
    if n_free < threshold or available() is None:
        why = "pyamg is not installed" if n_free >= threshold else f"{n_free:,} free DOFs < {threshold:,}"
        return LinearChoice("direct", f"auto: {why}")
    above = f"auto: {n_free:,} free DOFs ≥ {threshold:,}"
    if start is not None or direct_backend != "pardiso" or cost is None or n_free > ANALYSE_UP_TO:
        return LinearChoice("cg-amg", above)
    return _by_factorization_cost(cost(), above)


def _by_factorization_cost(found: "FactorCost | None", above: str) -> LinearChoice:
    if found is None:
        return LinearChoice("cg-amg", above)
    ratio = found.flops_per_nonzero
    what = (f"{above}, and PARDISO's analysis predicts ~{found.mflops / 1e3:.3g} GFLOP per factorization, "
            f"~{ratio:,.0f} flops per entry of K_ff")
    if ratio > FLOPS_PER_NONZERO:
        return LinearChoice("cg-amg", f"{what} > {FLOPS_PER_NONZERO:,}")
    fits = found.factor_bytes * 2 <= FACTOR_MEMORY_SHARE * _available_memory()
    if not fits:
        return LinearChoice("cg-amg", f"{what}, but its factor ({found.factor_bytes / 1e9:.3g} GB, "
                                      f"two kept) does not fit half the free memory")
    return LinearChoice("direct", f"{what} ≤ {FLOPS_PER_NONZERO:,}: a factorization costs less than "
                                  f"the CG iterations it replaces")


def _available_memory() -> float:
    import psutil

    return float(psutil.virtual_memory().available)


def supports(body) -> bool:
    """CG + AMG's near-nullspace is the 3D rigid-body modes: a 3D body with three displacement
    DOFs per node (not a plane sheet, nor a body with extra fields or none)."""
    space = getattr(body, "space", None)
    X = getattr(space, "node_coordinates", None)
    return X is not None and X.ndim == 2 and X.shape[1] == 3 and space.n_dofs == 3 * len(X)


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


class AMGHierarchy:
    """One smoothed-aggregation hierarchy, reused for every K_ff of a run while it stays fast.

    The V-cycle M⁻¹ built for one tangent K₀ stays symmetric positive definite, so it remains a
    valid CG (and LOBPCG) preconditioner for every later tangent of the same mesh; it only gets
    less effective as K drifts from K₀ (stiffening, softening). ``rate`` = CG iterations per
    decade of residual reduction, log₁₀(‖b‖ / ‖r‖); the first solve after a set-up fixes the
    baseline, and a solve slower than REBUILD_FACTOR × baseline marks the hierarchy stale, so the
    next request rebuilds it on the current K (``setups`` counts the set-ups). A hierarchy is
    rebuilt as well for a matrix of another size."""

    def __init__(self, near_nullspace: np.ndarray):
        self.B = near_nullspace
        self.setups = 0
        self.witness: np.ndarray | None = None  # CG's last pᵀKp ≤ 0 direction (vlab.fe.eigen_amg)
        self.eigenvectors: np.ndarray | None = None  # the last stability check's, for a warm start
        self.stale = True
        self.baseline: float | None = None
        self._ml = self._M = None
        self._n = -1

    def preconditioner(self, K: sp.csr_matrix):
        """M ≈ K⁻¹ (a pyamg LinearOperator): the current hierarchy, or a new one built on K."""
        if self.stale or K.shape[0] != self._n:
            self.rebuild(K)
        return self._M

    def rebuild(self, K: sp.csr_matrix) -> None:
        import pyamg

        # CG's dot products and the V-cycle's norms are O(n) BLAS-1 calls: threaded OpenBLAS
        # busy-waits between them and, on a loaded 2-core machine, took 20 ms per 14k-entry dot
        # product (3 µs serial; measured), i.e. 90 % of a V-cycle (vlab.fe.blas)
        serial_openblas()

        self._ml = pyamg.smoothed_aggregation_solver(
            K, B=self.B, symmetry="symmetric", max_coarse=300, coarse_solver="splu",
            improve_candidates=None, presmoother=SMOOTHER, postsmoother=SMOOTHER)
        self._M = self._ml.aspreconditioner(cycle="V")
        self._n, self.stale, self.baseline = K.shape[0], False, None
        self.setups += 1

    def record(self, iterations: int, decades: float) -> None:
        """Book one converged CG solve; mark the hierarchy stale on a measured slowdown."""
        if decades < 1.0:  # too short a solve to measure a rate
            return
        rate = iterations / decades
        if self.baseline is None:
            self.baseline = rate
        elif iterations >= MIN_ITERATIONS_TO_JUDGE and rate > REBUILD_FACTOR * self.baseline:
            self.stale = True


#: Damped Jacobi, ω = 4/(3 ρ(D⁻¹K)), one sweep before and after each coarse correction (the same
#: on both sides: the V-cycle stays symmetric, and positive definite as ω ρ = 4/3 < 2). pyamg's
#: default, symmetric Gauss–Seidel, needs fewer CG iterations (14 against 22 on a 24³ cube's
#: tangent at stretch 1.3) but its scalar sweeps cost 3× a matrix-vector product each, four per
#: V-cycle: CG to 1e-8 took 0.47 s with it and 0.31 s with Jacobi (benchmarks/RESULTS.md)
SMOOTHER = ("jacobi", {"omega": 4.0 / 3.0, "withrho": True})
REBUILD_FACTOR = 1.75  # CG iterations per decade, against those right after the set-up
MIN_ITERATIONS_TO_JUDGE = 8  # below this the count is too coarse to call a slowdown


class AMGConjugateGradient(Factorization):
    """Stands in for a factorization of K_ff: ``solve(b, rtol)`` runs preconditioned CG.

    ``hierarchy``: a shared AMGHierarchy (reused across Newton iterations, load steps and the
    stability check); None builds a private one. ``witness`` keeps the last direction p with
    pᵀK p ≤ 0 that CG met: a certificate that K is not positive definite (its Rayleigh quotient
    bounds λ_min from above), which the stability check uses as a start vector."""

    backend = "cg-amg"
    negative_pivots = None

    def __init__(self, K: sp.spmatrix, near_nullspace: np.ndarray | None = None,
                 hierarchy: AMGHierarchy | None = None):
        self._K = sp.csr_matrix(K)
        self.shape = self._K.shape
        self.iterations: list[int] = []
        self.witness: np.ndarray | None = None
        self.hierarchy = hierarchy or AMGHierarchy(near_nullspace)
        setups = self.hierarchy.setups
        self._M = _timed_preconditioner(self.hierarchy, self._K)
        self.fresh = self.hierarchy.setups > setups  # the hierarchy was built on this very K

    @property
    def K(self) -> sp.csr_matrix:
        return self._K

    @property
    def preconditioner(self):
        return self._M

    def solve(self, b: np.ndarray, rtol: float = DIRECT_TOLERANCE, x0: np.ndarray | None = None) -> np.ndarray:
        """x with ‖K x − b‖ ≤ rtol ‖b‖; a stale shared hierarchy that fails is rebuilt once.

        A right-hand side parallel to the last one (c b, to round-off) costs no solve: x = c x_last.
        The stability check's path slope vᵀKv and the next load step's predictor both solve
        K_ff v = K_fp Δu_p at the same converged state, with Δu_p = Δt û_p. ``x0``: a first guess
        (the same solve at the previous state; CG then starts from the residual b − K x0)."""
        b = np.asarray(b, dtype=float)
        scaled = self._parallel_to_last(b, rtol)
        if scaled is not None:
            return scaled
        try:
            x = self._cg(b, rtol, x0)
        except IterativeSolveFailed as exc:
            x = self._retry(b, rtol, exc)
        self._last = (b.copy(), x.copy(), rtol)
        return x

    _last: tuple | None = None

    def _parallel_to_last(self, b: np.ndarray, rtol: float) -> np.ndarray | None:
        if self._last is None or self._last[2] > rtol or len(self._last[0]) != len(b):
            return None
        b0, x0, _ = self._last
        bb = float(b0 @ b0)
        if bb == 0.0:
            return None
        c = float(b0 @ b) / bb
        if np.linalg.norm(b - c * b0) > 1e-14 * np.linalg.norm(b):
            return None
        return c * x0

    def _retry(self, b: np.ndarray, rtol: float, exc: IterativeSolveFailed) -> np.ndarray:
        """After a failed CG: rebuild a reused hierarchy on this K and solve once more; raise
        ``exc`` on negative curvature or when the hierarchy was built on this K already."""
        if self.witness is not None or self.fresh:
            raise exc
        log.info("CG with the reused AMG hierarchy failed (%s); rebuilding it", exc)
        self.hierarchy.stale, self.fresh = True, True
        self._M = _timed_preconditioner(self.hierarchy, self._K)
        return self._cg(b, rtol)

    @timed(LINEAR_SOLVE)
    def _cg(self, b: np.ndarray, rtol: float, x0: np.ndarray | None = None) -> np.ndarray:
        b = np.asarray(b, dtype=float)
        b_norm = math.sqrt(float(b @ b))
        x = np.zeros_like(b)
        if b_norm == 0.0:
            return x
        r = b.copy()
        if x0 is not None and len(x0) == len(b):
            x += x0
            r -= self._K @ x0
        if math.sqrt(float(r @ r)) <= rtol * b_norm:
            return x
        z = self._M @ r
        p = z.copy()
        rz = float(r @ z)
        for k in range(1, MAX_ITERATIONS + 1):
            Kp = self._K @ p
            curvature = float(p @ Kp)
            if not curvature > 0.0:
                self.witness = self.hierarchy.witness = p / max(float(np.linalg.norm(p)), 1e-300)
                raise IterativeSolveFailed(f"CG met negative curvature pᵀKp = {curvature:.3g} "
                                           f"(indefinite tangent) at iteration {k}")
            alpha = rz / curvature
            x += alpha * p
            r -= alpha * Kp
            r_norm = math.sqrt(float(r @ r))
            if r_norm <= rtol * b_norm:
                self.iterations.append(k)
                if x0 is None:  # a warm start's first decades are its slowest: not a rate to judge by
                    self.hierarchy.record(k, math.log10(b_norm / max(r_norm, 1e-300)))
                return x
            z = self._M @ r
            rz_new = float(r @ z)
            p *= rz_new / rz
            p += z
            rz = rz_new
        raise IterativeSolveFailed(f"CG did not reach {rtol:.1e} in {MAX_ITERATIONS} iterations")


@timed(LINEAR_SOLVE)
def _timed_preconditioner(hierarchy: AMGHierarchy, K: sp.csr_matrix):
    """The hierarchy's preconditioner for K; a (re)build is charged to the linear-solve phase."""
    return hierarchy.preconditioner(K)
