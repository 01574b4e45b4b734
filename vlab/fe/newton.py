"""Newton's method on the total energy for one load level, with an energy line search.

Equilibrium is a stationary point of W(u) over the free DOFs (prescribed DOFs fixed):
    r = ∂W/∂u_f = f_int,f (N),   K_ff Δu = -r,   u ← u + α Δu.
The step length α backtracks from 1 until the sufficient-decrease (Armijo) condition
    W(u + αΔu) <= W(u) + c α rᵀΔu
holds, a trial with J <= 0 anywhere counting as W = +inf. Close to the solution W changes by less
than its round-off, so a trial that cuts ‖r‖ by the same factor is accepted as well.

Exact Newton is the default, so quadratic convergence stays visible. A direction with rᵀΔu >= 0
(indefinite tangent) is not a descent direction: it is repaired with a diagonal shift
K_ff + τ diag|K_ff| (τ grown tenfold until descent), or as a last resort a scaled gradient step,
and the repair is counted.

Converged means ‖r_f‖ <= rtol · (force scale) and the last update ‖Δu‖∞ <= utol · (length scale);
both histories are recorded.

Factorization reuse (chord steps: one solve with a positive definite tangent factorized earlier,
instead of an assembly and a factorization), counted in ``NewtonRecord.reused``:
- the first correction of a load step uses the tangent already factorized at the last converged
  state (for the stability check and the predictor), if one is handed in;
- once ‖r_f‖ meets rtol but the last update still exceeds utol (the update criterion lags one
  step behind the residual), the confirming correction reuses the last factorization;
- once an exact Newton step has brought ‖r_f‖ within ``chord_band`` × rtol, the next correction
  reuses that step's factorization: the chord iteration contracts by ~‖K⁻¹ΔK‖, proportional to
  the last update, which is tiny there (measured on the ISO 527-2 1BA dogbone: 3.4e-8 →
  1.4e-12 in one chord step, where the exact step it replaces reached 5.7e-14).
Every other iteration is exact Newton, so quadratic convergence stays visible in the residual
history down to chord_band × rtol; a chord step that contracts poorly costs one solve and one
residual evaluation, and the next iteration refactorizes (chord steps never follow chord steps
above rtol).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from vlab.fe.assembly import Partition
from vlab.fe.iterative import (AMGConjugateGradient, IterativeSolveFailed, forcing_term,
                               rigid_body_modes)
from vlab.fe.linsolve import Factorization, SingularSystem, factorize
from vlab.fe.problem import Evaluation, HyperelasticBody

log = logging.getLogger(__name__)


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
    linear: str = "direct"  # or "cg-amg": exact corrections by CG + AMG (vlab.fe.iterative)


@dataclass
class NewtonRecord:
    """History of one Newton solve: relative residual per iterate, relative update per iteration."""

    residuals: list[float] = field(default_factory=list)
    updates: list[float] = field(default_factory=list)
    step_lengths: list[float] = field(default_factory=list)
    repairs: int = 0
    reused: int = 0  # corrections solved with a tangent factorized before this solve (chord)
    converged: bool = False
    reason: str = ""

    @property
    def iterations(self) -> int:
        return len(self.updates)


@dataclass(frozen=True)
class Tangent:
    """A factorized K_ff with its coupling block K_fp (used by the load-step predictor)."""

    factor: Factorization
    Kfp: sp.csr_matrix
    K: sp.csr_matrix | None = None  # the full tangent (free and prescribed), if kept


class TangentCache:
    """The tangent of the last state asked for, so that one assembly + factorization at a
    converged state serves the stability check, the next predictor and the first correction.

    A model whose tangent is constant (``material.is_linear``) is factorized once for the whole
    test. ``factorizations`` counts the factorizations made here."""

    def __init__(self, body: HyperelasticBody, partition: Partition):
        self.body, self.partition = body, partition
        self.factorizations = 0
        self._state: Evaluation | None = None
        self._tangent: Tangent | None = None
        self._constant = bool(getattr(getattr(body, "material", None), "is_linear", False))

    def at(self, evaluation: Evaluation) -> Tangent:
        """K, K_ff factorized and K_fp at ``evaluation`` (raises SingularSystem)."""
        if self._tangent is None or not (self._constant or evaluation is self._state):
            K = self.body.stiffness(evaluation)
            Kff, Kfp = self.partition.blocks(K)
            self._tangent = Tangent(factorize(Kff), Kfp, K)
            self._state = evaluation
            self.factorizations += 1
        return self._tangent

    def holds(self, evaluation: Evaluation) -> Tangent | None:
        """The cached tangent if it belongs to ``evaluation`` (no new work), else None."""
        if self._tangent is not None and (self._constant or evaluation is self._state):
            return self._tangent
        return None


class NewtonFailure(RuntimeError):
    def __init__(self, reason: str, record: NewtonRecord, evaluation: Evaluation | None):
        super().__init__(reason)
        self.reason = reason
        self.record = record
        self.evaluation = evaluation


def tangent_at(body: HyperelasticBody, partition: Partition, evaluation: Evaluation) -> Tangent:
    Kff, Kfp = partition.blocks(body.stiffness(evaluation))
    return Tangent(factorize(Kff), Kfp)


def solve_equilibrium(body: HyperelasticBody, partition: Partition, start: Evaluation,
                      scales: tuple[float, float], options: NewtonOptions,
                      first: Tangent | None = None,
                      ) -> tuple[Evaluation, NewtonRecord, Tangent | None]:
    """Newton iterations from the evaluated state ``start`` (prescribed DOFs at their targets).

    ``scales`` = (force scale floor in N, length scale in mm). ``first``: a positive definite
    factorized tangent near ``start`` for the first correction (chord step; see the module
    docstring), or None. Returns the converged evaluation, its record and the last tangent
    factorized (None if no iteration was needed). Raises NewtonFailure with the record on
    divergence, inadmissible states or singular tangents.
    """
    record = NewtonRecord()
    force_floor, length = scales
    free = partition.free
    ev = start
    if not ev.admissible:
        record.reason = (f"moving the grips alone leaves an element inverted or collapsed "
                         f"(min J = {ev.min_J:.3g} at element {ev.worst[0]})")
        raise NewtonFailure(record.reason, record, ev)
    tangent = last = None
    chord = False  # was the last correction a chord step
    for k in range(options.max_iterations + 1):
        r = ev.f_int[free]
        scale = max(force_floor, _norm(ev.f_int[partition.prescribed]))
        record.residuals.append(_norm(r) / scale)
        if record.residuals[-1] <= options.rtol and (k == 0 or record.updates[-1] <= options.utol):
            record.converged = True
            return ev, record, tangent
        if k == options.max_iterations:
            break
        if k == 0 and options.reuse_first_tangent:
            reusable = first
        elif k > 0 and options.reuse_last_tangent and (
                record.residuals[-1] <= options.rtol
                or (record.residuals[-1] <= options.chord_band * options.rtol and not chord)):
            reusable = last
        else:
            reusable = None
        chord = reusable is not None and (reusable.factor.negative_pivots == 0
                                          or reusable.factor.backend == "cg-amg")
        eta = forcing_term(record.residuals[-1], options.rtol)
        try:
            if chord:
                du = _solve(reusable.factor, -r, eta)
                record.reused += 1
            else:
                Kff, Kfp = partition.blocks(body.stiffness(ev))
                tangent, du = _exact_correction(body, partition, Kff, Kfp, r, eta, options)
            last = reusable if chord else tangent
        except SingularSystem as exc:
            record.reason = f"singular tangent: {exc}"
            raise NewtonFailure(record.reason, record, ev) from exc
        if not chord and not _dot(r, du) < 0.0:
            du = _repaired_direction(Kff, r)
            record.repairs += 1
        ev, alpha = _line_search(body, free, ev, du, options)
        if ev is None:
            record.reason = "line search found no admissible decrease along the Newton direction"
            raise NewtonFailure(record.reason, record, alpha)
        record.step_lengths.append(alpha)
        record.updates.append(alpha * float(np.max(np.abs(du), initial=0.0)) / length)
    record.reason = f"no convergence in {options.max_iterations} iterations"
    raise NewtonFailure(record.reason, record, ev)


def _solve(factor: Factorization, rhs: np.ndarray, eta: float) -> np.ndarray:
    """A direct solve, or an iterative one to the relative residual η (inexact Newton)."""
    if factor.backend == "cg-amg":
        return factor.solve(rhs, eta)
    return factor.solve(rhs)


def _exact_correction(body, partition: Partition, Kff, Kfp, r: np.ndarray, eta: float,
                      options: NewtonOptions) -> tuple[Tangent, np.ndarray]:
    """K_ff Δu = -r with the configured solver; CG + AMG falls back to a direct factorization
    when it meets an indefinite K_ff or does not converge."""
    if options.linear == "cg-amg":
        try:
            solver = AMGConjugateGradient(Kff, rigid_body_modes(body.space.node_coordinates)[partition.free])
            return Tangent(solver, Kfp), solver.solve(-r, eta)
        except IterativeSolveFailed as exc:
            log.info("CG + AMG failed (%s); direct factorization instead", exc)
    tangent = Tangent(factorize(Kff), Kfp)
    return tangent, tangent.factor.solve(-r)


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """aᵀb without BLAS: a BLAS level-1 call wakes its thread pool, which on a loaded machine
    cost ~10 ms per call (measured), more than the whole residual evaluation of a small mesh."""
    return float(np.einsum("i,i->", a, b))


def _norm(a: np.ndarray) -> float:
    return math.sqrt(_dot(a, a))


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


def _line_search(body: HyperelasticBody, free: np.ndarray, ev: Evaluation, du: np.ndarray,
                 options: NewtonOptions):
    """Backtracking on W; returns (accepted evaluation, α) or (None, last inadmissible trial)."""
    slope = _dot(ev.f_int[free], du)
    r0 = _norm(ev.f_int[free])
    alpha, last = 1.0, None
    for _ in range(options.max_backtracks):
        u = ev.u.copy()
        u[free] += alpha * du
        trial = body.evaluate(u)
        if trial.admissible:
            decrease = trial.W <= ev.W + options.sufficient_decrease * alpha * slope
            rn = _norm(trial.f_int[free])
            if decrease or rn <= (1.0 - options.sufficient_decrease * alpha) * r0:
                return trial, alpha
        last = trial
        alpha *= 0.5
    return None, last
