"""Newton's method on the total energy for one load level, with an energy line search.

Equilibrium is a stationary point of W(u) over the free DOFs (prescribed DOFs fixed):
    r = ∂W/∂u_f = f_int,f (N),   K_ff Δu = -r,   u ← u + α Δu.
The step length α backtracks from 1 until the sufficient-decrease (Armijo) condition
    W(u + αΔu) <= W(u) + c α rᵀΔu
holds, a trial with J <= 0 anywhere counting as W = +inf. Close to the solution W changes by less
than its round-off, so a trial that cuts ‖r‖ by the same factor is accepted as well. A full step
without sufficient decrease may still be taken, up to ``watchdog`` steps in a row, before the
iteration returns to where the sequence began and backtracks (vlab.fe.line_search.Watchdog: near
ν = ½ good full steps raise W); counted in ``NewtonRecord.relaxed`` and ``returns``.

A direction with rᵀΔu >= 0 (indefinite tangent) is not a descent direction: it is repaired with
a diagonal shift K_ff + τ diag|K_ff| (τ grown tenfold until descent), or as a last resort a
scaled gradient step, and the repair is counted.

Converged means ‖r_f‖ <= rtol · (force scale) and the last update ‖Δu‖∞ <= utol · (length scale);
both histories are recorded.

Factorization reuse (chord steps: one solve with a positive definite tangent K̃ factorized
earlier, instead of an assembly and a factorization), counted in ``NewtonRecord.reused``. A chord
step maps the residual by r₊ ≈ (I − K K̃⁻¹) r, a linear contraction by ~‖K̃⁻¹(K − K̃)‖ where exact
Newton converges quadratically; it pays when a solve and a residual evaluation cost much less
than an assembly and a factorization, which they do (ISO 527-2 1BA dogbone, 21k DOFs: 4 + 7 ms
against 33 + 49 ms, measured with pyinstrument).
- the first correction of a load step uses the tangent already factorized at the last converged
  state (for the stability check and the predictor), if one is handed in;
- ``chord_contraction`` > 0 (``solver.newton = "reuse"``, the default): a chord step that cut
  ‖r_f‖ by at least that factor is followed by another with the same factor, if at that rate
  rtol is at most ``chord_horizon`` (3) steps away (each costs ~1/8 of an exact step, but it
  is an iteration, and exact Newton would get there in one or two). The chord steps made with one
  factor keep their pairs (s, y) = (Δu_f, Δr_f) and apply the BFGS update of K̃⁻¹ (two-loop
  recursion; a pair without curvature, sᵀy ≤ 0, is dropped, so the update stays positive
  definite and the direction a descent one): the secant pairs learn K − K̃ along the directions
  the iteration explores, which on the blocks turns the second chord step's 1.1e-6 → 1.6e-8 into
  1.1e-6 → 1.2e-11. With the cubic predictor of vlab.fe.stepping a load step starts at
  ‖r‖ ~ 1e-5, and the stability check's factor converges it in two or three solves with no
  factorization of its own (blocks, 10 steps: 21 iterations and 11 factorizations against 21 and
  21 exact; dogbone: 28 and 12 against 21 and 21). A step that contracts less (a stiffening or
  softening tangent, plasticity switching on) is followed by exact Newton;
- once ‖r_f‖ meets rtol but the last update still exceeds utol (the update criterion lags one
  step behind the residual), the confirming correction reuses the last factorization;
- once an exact Newton step has brought ‖r_f‖ within ``chord_band`` × rtol, the next correction
  reuses that step's factorization: the chord iteration contracts by ~‖K⁻¹ΔK‖, proportional to
  the last update, which is tiny there (measured on the dogbone: 3.4e-8 → 1.4e-12 in one chord
  step, where the exact step it replaces reached 5.7e-14).
Every other iteration is exact Newton. ``chord_contraction = 0`` (``solver.newton = "exact"``)
keeps only the first and the last two rules, so quadratic convergence shows in the residual
history down to chord_band × rtol (the way to see that a tangent is consistent); a chord step
that contracts poorly costs one solve and one residual evaluation, and the next iteration
refactorizes.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from vlab.fe.assembly import Partition
from vlab.fe.iterative import AMGConjugateGradient, AMGHierarchy, IterativeSolveFailed, forcing_term
from vlab.fe.line_search import Watchdog, dot as _dot, norm as _norm
from vlab.fe.roundoff import roundoff_floor, stall_explanation
from vlab.fe.linsolve import Factorization, SingularSystem, factorize
from vlab.fe.system import System
from vlab.fe.problem import Evaluation
from vlab.fe.tangents import Tangent, TangentCache, amg_modes, tangent_at  # noqa: F401  (re-exported)

log = logging.getLogger(__name__)


CHORD_CONTRACTION = 0.1  # a chord step that gains a decade costs ~1/8 of an exact one (dogbone)
WATCHDOG_STEPS = 3  # Cook's membrane ν = 0.4999: the energy comes back below its reference in 2


@dataclass(frozen=True)
class NewtonOptions:
    rtol: float = 1e-8
    utol: float = 1e-6
    max_iterations: int = 25
    max_backtracks: int = 30
    sufficient_decrease: float = 1e-4
    reuse_first_tangent: bool = True
    reuse_last_tangent: bool = True
    chord_band: float = 100.0  # reuse the last exact factor from ‖r‖ ≤ chord_band · rtol on
    chord_contraction: float = CHORD_CONTRACTION  # keep a reused factor while a chord step cuts ‖r‖ by this
    chord_secant: bool = True  # BFGS-update the reused factor with the chord steps' (Δu, Δr)
    chord_horizon: float = 3.0  # ... and reaches rtol at that rate within this many more steps
    linear: str = "direct"  # or "cg-amg": exact corrections by CG + AMG (vlab.fe.iterative)
    watchdog: int = WATCHDOG_STEPS  # full Newton steps allowed without sufficient decrease (0: monotone)


@dataclass
class NewtonRecord:
    """History of one Newton solve: relative residual per iterate, relative update per iteration."""

    residuals: list[float] = field(default_factory=list)
    updates: list[float] = field(default_factory=list)
    step_lengths: list[float] = field(default_factory=list)
    repairs: int = 0
    relaxed: int = 0  # full steps taken without sufficient decrease (watchdog)
    returns: int = 0  # watchdog returns to the reference state (the relaxed steps wasted)
    reused: int = 0  # corrections solved with a tangent factorized before this solve (chord)
    iterative: int = 0  # exact corrections solved by CG + AMG (no factorization)
    converged: bool = False
    reason: str = ""

    @property
    def iterations(self) -> int:
        return len(self.updates)

    @property
    def exact(self) -> int:
        """Iterations that assembled and factorized a new tangent (the others reused one)."""
        return self.iterations - self.reused

    @property
    def factorized(self) -> int:
        """Iterations that factorized a tangent (exact ones not solved by CG + AMG)."""
        return self.exact - self.iterative


class NewtonFailure(RuntimeError):
    def __init__(self, reason: str, record: NewtonRecord, evaluation: Evaluation | None):
        super().__init__(reason)
        self.reason = reason
        self.record = record
        self.evaluation = evaluation


@dataclass(frozen=True)
class Equilibrium:
    """A converged Newton solve: the state, its record, the last tangent factorized (None if no
    iteration was needed)."""

    evaluation: Evaluation
    record: NewtonRecord
    tangent: Tangent | None


def solve_equilibrium(system: System, start: Evaluation, options: NewtonOptions,
                      first: Tangent | None = None, hierarchy: AMGHierarchy | None = None) -> Equilibrium:
    """Newton iterations from the evaluated state ``start`` (prescribed DOFs at their targets).

    ``system.scales`` = (force scale floor in N, length scale in mm). ``first``: a positive
    definite factorized tangent near ``start`` for the first correction (chord step; see the
    module docstring), or None. ``hierarchy``: the run's shared AMG hierarchy for CG corrections
    (None: a new one per correction). Raises NewtonFailure with the record on divergence,
    inadmissible states or singular tangents.
    """
    it = _Iteration(system, options, first, hierarchy)
    ev = start
    if not ev.admissible:
        it.record.reason = (f"moving the grips alone leaves an element inverted or collapsed "
                            f"(min J = {ev.min_J:.3g} at element {ev.worst[0]})")
        raise NewtonFailure(it.record.reason, it.record, ev)
    for k in range(options.max_iterations + 1):
        r, scale = it.residual(ev)
        if it.converged(ev, k):
            it.record.converged = True
            return Equilibrium(ev, it.record, it.tangent)
        if k == options.max_iterations:
            break
        ev = it.step(k, ev, r)
    floor = roundoff_floor(system.body, system.partition, ev, scale)
    it.record.reason = (f"no convergence in {options.max_iterations} iterations"
                        + stall_explanation(it.record.residuals, options.rtol, floor))
    raise NewtonFailure(it.record.reason, it.record, ev)


class _Iteration:
    """The state one Newton solve carries from iteration to iteration."""

    def __init__(self, system: System, options: NewtonOptions, first: Tangent | None,
                 hierarchy: AMGHierarchy | None):
        self.system, self.options, self.first, self.hierarchy = system, options, first, hierarchy
        self.record = NewtonRecord()
        self.tangent = self.last = None
        self.memory = _SecantMemory(None)
        self.watchdog = Watchdog(options.watchdog)
        self.chord = False  # was the last correction a chord step

    def residual(self, ev: Evaluation) -> tuple[np.ndarray, float]:
        """r_f, and the force scale its norm is relative to (recorded)."""
        partition = self.system.partition
        r = ev.f_int[partition.free]
        scale = max(self.system.scales[0], _norm(ev.f_int[partition.prescribed]))
        self.record.residuals.append(_norm(r) / scale)
        return r, scale

    def converged(self, ev: Evaluation, k: int) -> bool:
        rec, o = self.record, self.options
        return (rec.residuals[-1] <= o.rtol and (k == 0 or rec.updates[-1] <= o.utol)
                and ev.constraint <= o.rtol)

    def step(self, k: int, ev: Evaluation, r: np.ndarray) -> Evaluation:
        """One correction and its line search; the new state."""
        record, options, free = self.record, self.options, self.system.partition.free
        reusable = _reusable(k, record, options, self.first, self.last, self.chord)
        self.chord = reusable is not None and (reusable.factor.negative_pivots == 0
                                               or reusable.factor.backend == "cg-amg")
        du = self._direction(ev, r, reusable)
        returns = record.returns
        ev, alpha, du = self.watchdog.advance(self.system.body, free, ev, du, options, record)
        if ev is None:
            record.reason = "line search found no admissible decrease along the Newton direction"
            raise NewtonFailure(record.reason, record, alpha)
        if (self.chord and options.chord_secant and reusable.factor.backend != "cg-amg"
                and record.returns == returns):
            self.memory.add(alpha * du, ev.f_int[free] - r)  # (CG is not a fixed linear K̃⁻¹)
        record.step_lengths.append(alpha)
        record.updates.append(alpha * float(np.max(np.abs(du), initial=0.0)) / self.system.scales[1])
        return ev

    def _direction(self, ev: Evaluation, r: np.ndarray, reusable: Tangent | None) -> np.ndarray:
        """Δu_f: a chord step with ``reusable`` (BFGS-updated), or exact Newton (repaired if it
        is no descent direction)."""
        body, partition, record = self.system.body, self.system.partition, self.record
        eta = forcing_term(record.residuals[-1], self.options.rtol)
        try:
            if self.chord:
                if self.memory.factor is not reusable.factor:
                    self.memory = _SecantMemory(reusable.factor)
                du = self.memory.direction(r, lambda rhs: _solve(reusable.factor, rhs, eta))
                record.reused += 1
                self.last = reusable
                return du
            Kff, Kfp = partition.blocks(body.stiffness(ev))
            self.tangent, du = _exact_correction(body, partition, Kff, Kfp, r, eta, self.options,
                                                 self.hierarchy)
            self.last = self.tangent
            record.iterative += self.tangent.factor.backend == "cg-amg"
        except SingularSystem as exc:
            record.reason = f"singular tangent: {exc}"
            raise NewtonFailure(record.reason, record, ev) from exc
        if not _dot(r, du) < 0.0:
            du = _repaired_direction(Kff, r)
            record.repairs += 1
        return du


def _reusable(k: int, record: NewtonRecord, options: NewtonOptions, first: Tangent | None,
              last: Tangent | None, chord: bool) -> Tangent | None:
    """The factorized tangent iteration k may reuse (a chord step), or None (factorize anew):
    ``first`` for the first correction; later the last one while it pays (module docstring)."""
    if k == 0 and options.reuse_first_tangent:
        return first
    if k > 0 and options.reuse_last_tangent and (
            record.residuals[-1] <= options.rtol
            or (record.residuals[-1] <= options.chord_band * options.rtol and not chord)
            or (chord and _chord_pays(record.residuals, options))):
        return last
    return None



class _SecantMemory:
    """BFGS pairs (s, y) = (Δu_f, Δr_f) of the chord steps made with one factor K̃.

    ``direction(r)`` = −H r with H = K̃⁻¹ updated by every pair in turn,
        H₊ = (I − ρ s yᵀ) H (I − ρ y sᵀ) + ρ s sᵀ,   ρ = 1 / (yᵀs)   (mm/N),
    applied by the two-loop recursion (one solve with K̃, 4 dot products per pair), so that
    H₊ y = s for the last pair: the secant equation of the energy's Hessian along s."""

    def __init__(self, factor):
        self.factor, self.pairs = factor, []

    def add(self, s: np.ndarray, y: np.ndarray) -> None:
        sy = _dot(s, y)
        if sy > 0.0:
            self.pairs.append((s, y, 1.0 / sy))

    def direction(self, r: np.ndarray, solve) -> np.ndarray:
        q = -r
        alphas = []
        for s, y, rho in reversed(self.pairs):
            a = rho * _dot(s, q)
            q = q - a * y
            alphas.append(a)
        z = solve(q)
        for (s, y, rho), a in zip(self.pairs, reversed(alphas)):
            z = z + s * (a - rho * _dot(y, z))
        return z


def _chord_pays(residuals: list[float], options: NewtonOptions) -> bool:
    """After a chord step that contracted ‖r‖ by ρ = r_k / r_(k−1): another one pays if
    ρ ≤ chord_contraction and, at that rate, rtol is at most ``chord_horizon`` steps away
    (log(rtol / r_k) / log ρ); otherwise one exact step (quadratic from here) is cheaper."""
    rho = residuals[-1] / residuals[-2] if residuals[-2] > 0.0 else 1.0
    if not 0.0 < rho <= options.chord_contraction:
        return False
    return math.log(options.rtol / residuals[-1]) / math.log(rho) <= options.chord_horizon


def _solve(factor: Factorization, rhs: np.ndarray, eta: float) -> np.ndarray:
    """A direct solve, or an iterative one to the relative residual η (inexact Newton)."""
    if factor.backend == "cg-amg":
        return factor.solve(rhs, eta)
    return factor.solve(rhs)


def _exact_correction(body, partition: Partition, Kff, Kfp, r: np.ndarray, eta: float,
                      options: NewtonOptions, hierarchy: AMGHierarchy | None = None) -> tuple[Tangent, np.ndarray]:
    """K_ff Δu = -r with the configured solver; CG + AMG (the shared hierarchy if given) falls
    back to a direct factorization when it meets an indefinite K_ff or does not converge."""
    if options.linear == "cg-amg":
        try:
            solver = AMGConjugateGradient(Kff, None if hierarchy else amg_modes(body, partition), hierarchy)
            return Tangent(solver, Kfp), solver.solve(-r, eta)
        except IterativeSolveFailed as exc:
            log.info("CG + AMG failed (%s); direct factorization instead", exc)
    tangent = Tangent(factorize(Kff), Kfp)
    return tangent, tangent.factor.solve(-r)


def _repaired_direction(Kff: sp.csr_matrix, r: np.ndarray) -> np.ndarray:
    """A descent direction from a shifted tangent K_ff + τ diag|K_ff|, else a scaled gradient."""
    d = np.abs(Kff.diagonal())
    d[d == 0.0] = 1.0
    for tau in 10.0 ** np.arange(-4, 3):
        try:
            du = factorize(Kff + sp.diags(tau * d)).solve(-r)
        except SingularSystem:
            continue
        if _dot(r, du) < 0.0:
            return du
    return -r / d
