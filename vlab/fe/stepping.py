"""Displacement-controlled load stepping with a tangent predictor and automatic cutback.

The grips prescribe u_p(t) = t · û_p for a load parameter t (0 = unloaded, 1 = target). Each
scheduled level is reached in one or more substeps. A substep starts from the linearised response
of the last factorized tangent,
    Δu_f = -K_ff⁻¹ K_fp Δu_p,
which for the linear model is already the exact solution (so it runs no Newton iteration and
reuses one factorization for the whole test). When the tangent at the converged state itself is
already factorized (the stability check needs it: ``Stepping.tangents``), the predictor and the
first Newton correction use it, so that factorization is not wasted. A substep that fails (no convergence, inverted
element, singular tangent) is retried from the last converged state with half the increment; easy
substeps let the increment grow back. A level may be cut back at most ``max_cutbacks`` times in
all (not only in a row: near a limit point halving and regrowing would otherwise creep towards
the limit forever); then the test stops with a diagnosis. An optional acceptance check
(``Stepping.accept``, e.g. the stability monitor) may reject a converged substep; that too cuts
back, and since the increment may not shrink below the level's first increment / 2^max_cutbacks,
a critical load level is bracketed to within that increment instead of being approached forever.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from vlab.fe.assembly import Partition
from vlab.fe.linsolve import SingularSystem
from vlab.fe.newton import (NewtonFailure, NewtonOptions, NewtonRecord, Tangent, TangentCache,
                            solve_equilibrium)
from vlab.fe.problem import Evaluation, HyperelasticBody

EASY_ITERATIONS = 4


@dataclass(frozen=True)
class Level:
    """A converged state at a scheduled load level t."""

    t: float
    evaluation: Evaluation
    newton: list[NewtonRecord]
    cutbacks: int

    @property
    def iterations(self) -> int:
        return sum(rec.iterations for rec in self.newton)


@dataclass(frozen=True)
class Failure:
    """Why a test stopped: the level it was heading for, the last converged t, the history."""

    level: int
    t_target: float
    t_attempted: float
    t_converged: float
    reason: str
    residuals: list[float]
    min_J: float | None = None
    element: int | None = None
    quadrature_point: int | None = None


@dataclass
class SolveHistory:
    levels: list[Level] = field(default_factory=list)
    failure: Failure | None = None
    factorizations: int = 0
    seconds: float = 0.0


# accept(evaluation, t) -> None, or the reason why a converged substep is rejected (e.g. unstable)
Acceptance = Callable[[Evaluation, float], "str | None"]


@dataclass(frozen=True)
class Stepping:
    """``accept`` vets every converged substep; a rejection is handled like a failed substep.

    ``tangents``: the tangent cache shared with ``accept`` (None: a private one)."""

    schedule: np.ndarray
    max_cutbacks: int = 8
    newton: NewtonOptions = NewtonOptions()
    accept: Acceptance | None = None
    tangents: TangentCache | None = None


def run_schedule(body: HyperelasticBody, partition: Partition, u_hat: np.ndarray,
                 stepping: Stepping, scales: tuple[float, float],
                 on_level: Callable[[Level], None] | None = None) -> SolveHistory:
    """Follow ``stepping.schedule`` (increasing or not) from the unloaded state."""
    start = time.perf_counter()
    history = SolveHistory()
    u = np.zeros(body.space.n_dofs)
    current = body.evaluate(u)
    cache = stepping.tangents or TangentCache(body, partition)
    try:
        tangent = cache.at(current)
    except SingularSystem as exc:
        history.failure = Failure(0, float(stepping.schedule[0]), 0.0, 0.0,
                                  f"the unloaded tangent is singular: the grips leave the specimen "
                                  f"free to move ({exc})", [])
        return _finish(history, start, cache, 0)
    newton_factorizations = 0
    t = 0.0
    for index, target in enumerate(stepping.schedule, start=1):
        dt, cutbacks, records = target - t, 0, []
        smallest = abs(dt) / 2.0**stepping.max_cutbacks
        while t != target:
            t_try = target if abs(target - t) <= abs(dt) * (1 + 1e-12) else t + dt
            converged_tangent = cache.holds(current)
            try:
                candidate, record, new_tangent = _substep(body, partition, current,
                                                          converged_tangent or tangent, u_hat, t,
                                                          t_try, stepping, scales,
                                                          converged_tangent)
                objection = stepping.accept and stepping.accept(candidate, float(t_try))
                if objection:
                    raise NewtonFailure(objection, record, None)
                current = candidate
            except NewtonFailure as failure:
                records.append(failure.record)
                newton_factorizations += failure.record.iterations - failure.record.reused
                cutbacks, dt = cutbacks + 1, dt / 2
                if cutbacks > stepping.max_cutbacks or abs(dt) < smallest * (1 - 1e-12):
                    history.failure = _diagnose(index, target, t_try, t, failure)
                    return _finish(history, start, cache, newton_factorizations)
                continue
            records.append(record)
            newton_factorizations += record.iterations - record.reused
            tangent = cache.holds(current) or new_tangent or tangent
            t = t_try
            if record.iterations <= EASY_ITERATIONS:
                dt *= 2.0
        level = Level(float(t), current, records, cutbacks)
        history.levels.append(level)
        if on_level is not None:
            on_level(level)
    return _finish(history, start, cache, newton_factorizations)


def _finish(history: SolveHistory, start: float, cache: TangentCache, newton_factorizations: int):
    history.factorizations = cache.factorizations + newton_factorizations
    history.seconds = time.perf_counter() - start
    return history


def _substep(body, partition, current: Evaluation, tangent: Tangent, u_hat, t0, t1,
             stepping: Stepping, scales, converged_tangent: Tangent | None = None):
    """Move the grips from t0 to t1, predict the free DOFs, then iterate to equilibrium.

    If the full tangent prediction inverts an element (large increments near a limit point), it
    is scaled back; the plain grip jump (scale 0) is the last candidate."""
    prescribed, free = partition.prescribed, partition.free
    du_p = (t1 - t0) * u_hat[prescribed]
    predicted = -tangent.factor.solve(tangent.Kfp @ du_p)
    for scale in (1.0, 0.5, 0.25, 0.0):
        u = current.u.copy()
        u[prescribed] += du_p
        u[free] += scale * predicted
        start = body.evaluate(u)
        if start.admissible:
            break
    return solve_equilibrium(body, partition, start, scales, stepping.newton, converged_tangent)


def _diagnose(index: int, target: float, attempted: float, converged: float,
              failure: NewtonFailure) -> Failure:
    ev = failure.evaluation
    inverted = ev is not None and not ev.admissible
    return Failure(
        level=index, t_target=float(target), t_attempted=float(attempted),
        t_converged=float(converged), reason=failure.reason,
        residuals=list(failure.record.residuals),
        min_J=None if ev is None else ev.min_J,
        element=ev.worst[0] if inverted else None,
        quadrature_point=ev.worst[1] if inverted else None,
    )
