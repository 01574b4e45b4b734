"""Displacement-controlled load stepping with a path predictor and automatic cutback.

The grips prescribe u_p(t) = t · û_p for a load parameter t (0 = unloaded, 1 = target). Each
scheduled level is reached in one or more substeps. A substep starts from the linearised response
of the last factorized tangent,
    Δu_f = -K_ff⁻¹ K_fp Δu_p,
which for the linear model is already the exact solution (so it runs no Newton iteration and
reuses one factorization for the whole test); past the first level the path is extrapolated
further (``path_increment``: the cubic through u and du/dt at the last two converged states).
When the tangent at the converged state itself is already factorized (the stability check
needs it: ``Stepping.tangents``), the predictor and the first Newton correction use it, so that
factorization is not wasted. A substep that fails (no convergence, inverted element, singular
tangent) is retried from the last converged state with half the increment; easy
substeps let the increment grow back. A level may be cut back at most ``max_cutbacks`` times in
all (not only in a row: near a limit point halving and regrowing would otherwise creep towards
the limit forever); then the test stops with a diagnosis. An optional acceptance check
(``Stepping.accept``, e.g. the stability monitor) may reject a converged substep; that too cuts
back, and since the increment may not shrink below the level's first increment / 2^max_cutbacks,
a critical load level is bracketed to within that increment instead of being approached forever.

Time and history (only when a scene asks for them; the elastic loop does none of this): levels
may carry a physical time (``Stepping.times``, s). A substep covering the fraction [s, s'] of a
level's segment advances the time by (s' − s)(τ_k − τ_{k−1}), so a cut-back substep also halves
the time step; a hold (t constant, time advancing) is a segment like any other. A body with
history (``body.history``, vlab.fe.body.HistoryCapability) is told the substep's time step before the solve and commits its state
only after the substep converged and was accepted. Levels flagged in ``Stepping.force_held`` hold
the moving grip's force instead of its position (creep; vlab.fe.force_control): t is then solved
for, at the force reached when the hold began or, with ``Stepping.force_targets`` (N), at a
force moving linearly from the last level's to the level's target over the substeps. A body
with a dead load (``f_ext``) is first brought to equilibrium under it at t = 0.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from vlab.fe.assembly import Partition
from vlab.fe.force_control import generalized_force, solve_force_controlled
from vlab.fe.inertia import factorized_inertia
from vlab.fe.linsolve import SingularSystem
from vlab.fe.newton import (NewtonFailure, NewtonOptions, NewtonRecord, Tangent, TangentCache,
                            solve_equilibrium)
from vlab.fe.problem import Evaluation
from vlab.fe.system import System

EASY_ITERATIONS = 4
# what was measured: a (numerically) zero pivot of K_ff at rest; vlab.run tells a free rigid-body
# mode (the grips leave one free) from ill-conditioning (they do not) with the geometric check
UNLOADED_SINGULAR = "the unloaded tangent is singular"


MAX_EXTRAPOLATION = 4.0  # largest Δt / h the path extrapolation of the predictor spans
CURVATURE_TRUST = 0.5    # largest ‖extrapolated − tangent step‖ / ‖tangent step‖ the predictor uses


@dataclass(frozen=True)
class PathPoint:
    """A converged state on the equilibrium path, for the load-step predictor: load parameter t,
    displacement u (all DOFs, mm) and, if known, the path derivative du_f/dt of the free DOFs
    from the tangent at that state (mm per unit t)."""

    t: float
    u: np.ndarray
    velocity: np.ndarray | None = None


@dataclass(frozen=True)
class Level:
    """A converged state at a scheduled load level t.

    ``state`` is the converged Evaluation. Once the level's observers have read it (the
    measurements, vlab.fe.stepping.run_schedule), the history keeps it ``released``: without its
    deformation gradient F (3·3·n_qp doubles per element, 576 B per Q1 hexahedron, one of the
    largest arrays of a large run, times the number of levels), which ``evaluation`` rebuilds
    from u with the body's ``gradient`` (bit for bit the F the solver had) on every read."""

    t: float
    state: Evaluation
    newton: list[NewtonRecord]
    cutbacks: int
    time: float | None = None  # physical time, s (None for a quasi-static test)
    gradient: Callable[[np.ndarray], np.ndarray] | None = None  # u -> F once F is released

    @property
    def evaluation(self) -> Evaluation:
        if self.gradient is None:
            return self.state
        return replace(self.state, F=self.gradient(self.state.u))

    def released(self, gradient: Callable[[np.ndarray], np.ndarray] | None) -> "Level":
        """This level without F in memory (itself if the body cannot rebuild F: ``gradient`` None)."""
        if gradient is None or self.gradient is not None:
            return self
        return replace(self, state=replace(self.state, F=None), gradient=gradient)

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
    u_converged: np.ndarray | None = None  # the last converged state's displacements (mm)


@dataclass
class SolveHistory:
    levels: list[Level] = field(default_factory=list)
    failure: Failure | None = None
    factorizations: int = 0
    seconds: float = 0.0
    amg_setups: int = 0  # set-ups of the shared AMG hierarchy (iterative path; 0 on the direct one)


# accept(evaluation, t) -> None, or the reason why a converged substep is rejected (e.g. unstable)
Acceptance = Callable[[Evaluation, float], "str | None"]


@dataclass(frozen=True)
class Stepping:
    """``accept`` vets every converged substep; a rejection is handled like a failed substep."""

    schedule: np.ndarray
    max_cutbacks: int = 8
    newton: NewtonOptions = NewtonOptions()
    accept: Acceptance | None = None
    times: np.ndarray | None = None  # physical time (s) at each level; None = quasi-static
    force_held: np.ndarray | None = None  # True where a level holds the moving grip's force
    force_targets: np.ndarray | None = None  # N, grip force reached at each force-held level
    tangents: TangentCache | None = None  # shared with the stability monitor


def run_schedule(system: System, stepping: Stepping,
                 on_level: Callable[[Level], None] | None = None) -> SolveHistory:
    """Follow ``stepping.schedule`` (increasing or not) from the unloaded state."""
    start = time.perf_counter()
    history = SolveHistory()
    cache = stepping.tangents or TangentCache(system.body, system.partition)
    cache.use_linear(stepping.newton.linear)  # the iterative path: no factorization at all
    walk = _unloaded(system, stepping, cache, history)
    if walk is None:
        return _finish(history, start, cache, 0)
    for index, target in enumerate(stepping.schedule, start=1):
        level = _level(system, stepping, cache, walk, index, target)
        if isinstance(level, Failure):
            history.failure = level
            break
        if on_level is not None:
            on_level(level)
        history.levels.append(level.released(system.body.gradient))
    return _finish(history, start, cache, walk.factorizations)


@dataclass
class _Walk:
    """What the stepping carries from substep to substep along the path."""

    current: Evaluation  # the last converged state
    tangent: Tangent  # the last factorized tangent (the predictor's)
    t: float = 0.0  # load parameter of ``current``
    clock: float = 0.0  # physical time of ``current``, s
    held_force: float | None = None  # Q* held (force control), N·mm
    previous: PathPoint | None = None  # the converged state before ``current``, for the predictor
    factorizations: int = 0  # Newton's own (the tangent cache counts its own)


@dataclass(frozen=True)
class _Step:
    evaluation: Evaluation
    t: float
    record: NewtonRecord
    tangent: Tangent | None
    here: PathPoint | None


def _unloaded(system: System, stepping: Stepping, cache: TangentCache, history: SolveHistory) -> "_Walk | None":
    """The unloaded state (settled under a dead load), its tangent checked for free rigid-body
    modes; None, with ``history.failure`` set, if there is none."""
    body = system.body
    current = body.evaluate(np.zeros(body.space.n_dofs))
    try:
        if body.f_ext is not None:  # settle under a dead load (self-weight) first
            current = _settled(system, current, stepping)
        tangent = cache.at(current)
        _check_restrained(tangent, system.partition)
    except NewtonFailure as exc:
        history.failure = Failure(0, float(stepping.schedule[0]), 0.0, 0.0,
                                  f"no equilibrium under the specimen's own weight: {exc.reason}",
                                  list(exc.record.residuals))
        return None
    except SingularSystem as exc:
        history.failure = Failure(0, float(stepping.schedule[0]), 0.0, 0.0,
                                  f"{UNLOADED_SINGULAR} ({exc})", [])
        return None
    return _Walk(current, tangent)


class Rejected(NewtonFailure):
    """A substep that converged to a state ``stepping.accept`` rejected (unstable, a limit point)."""


@dataclass
class _Cutbacks:
    """The substep fractions [s, s + ds] of one level's segment: halved on a failure, doubled
    after an easy step, never beyond a rejected state (the ``ceiling``, lifted if a state there
    is accepted after all). Past a loss of stability Newton may stagnate (a perfectly plastic
    strip: residual 3.6e-8 for 20 iterations with SuperLU), and the run must stop on the
    instability it found, not on a non-convergence beyond it."""

    max_cutbacks: int
    ds: float = 1.0
    count: int = 0
    ceiling: float = 1.0
    rejected: tuple | None = None  # (t, Rejected) of the last rejection

    def next_try(self, s: float) -> float:
        return min(1.0 if 1.0 - s <= self.ds * (1 + 1e-12) else s + self.ds, self.ceiling)

    def failed(self, failure: NewtonFailure, s_try: float, t_try: float) -> tuple | None:
        """Halve the substep; the (t, failure) to diagnose once the cutbacks run out, else None."""
        self.count, self.ds = self.count + 1, self.ds / 2
        if isinstance(failure, Rejected):
            self.ceiling, self.rejected = min(self.ceiling, s_try), (t_try, failure)
        if self.count > self.max_cutbacks or self.ds < (1 - 1e-12) / 2.0**self.max_cutbacks:
            return self.rejected or (t_try, failure)
        return None

    def accepted(self, s_try: float, easy: bool) -> None:
        if s_try >= self.ceiling:
            self.ceiling = 1.0
        if easy:
            self.ds *= 2.0


def _level(system: System, stepping: Stepping, cache: TangentCache, walk: _Walk, index: int,
           target) -> "Level | Failure":
    """Reach scheduled level ``index`` (load parameter ``target``) in substeps (``_Cutbacks``);
    the Failure if the cutbacks run out (the last rejection if any: the instability found)."""
    history = system.body.history
    t0, clock0 = walk.t, walk.clock
    span = (float(stepping.times[index - 1]) - clock0) if stepping.times is not None else 0.0
    held = stepping.force_held is not None and bool(stepping.force_held[index - 1])
    q0 = _held_forces(system, stepping, walk, index) if held else None
    steps, s, records = _Cutbacks(stepping.max_cutbacks), 0.0, []
    while s < 1.0:
        s_try = steps.next_try(s)
        t_try = target if s_try == 1.0 else t0 + s_try * (target - t0)
        if history is not None:
            history.begin_increment((s_try - s) * span)
        try:
            step = _attempt(system, stepping, cache, walk, t_try,
                            None if q0 is None else q0 + s_try * (walk.held_force - q0))
        except NewtonFailure as failure:
            records.append(failure.record)
            walk.factorizations += failure.record.factorized
            stop = steps.failed(failure, s_try, t_try)
            if stop is not None:
                return _diagnose(index, target, *stop, walk.t, walk.current.u)
            continue
        if history is not None:
            history.commit(walk.current)
        records.append(step.record)
        walk.factorizations += step.record.factorized
        walk.tangent = cache.holds(walk.current) or step.tangent or walk.tangent
        walk.t, s = step.t, s_try
        walk.clock = clock0 + s * span
        steps.accepted(s_try, step.record.iterations <= EASY_ITERATIONS)
    return Level(float(walk.t), walk.current, records, steps.count,
                 None if stepping.times is None else float(stepping.times[index - 1]))


def _held_forces(system: System, stepping: Stepping, walk: _Walk, index: int) -> float:
    """Q₀ of a force-held level; sets ``walk.held_force`` to the Q* it moves to: the force
    reached when the hold started, or û_m F* on a force-controlled ramp."""
    if walk.held_force is None:
        walk.held_force = generalized_force(walk.current, system.u_hat)  # the force when the hold starts
    q0 = walk.held_force
    if stepping.force_targets is not None:  # Q* = û_m F*: a force-controlled ramp
        travel = float(system.u_hat[np.argmax(np.abs(system.u_hat))])  # û_m (signed), mm
        q0, walk.held_force = (generalized_force(walk.current, system.u_hat),
                               travel * float(stepping.force_targets[index - 1]))
    return q0


def _attempt(system: System, stepping: Stepping, cache: TangentCache, walk: _Walk, t_try,
             q_target: float | None) -> _Step:
    """One substep to ``t_try`` (under force control: to the held force ``q_target``), vetted by
    ``stepping.accept``; on success ``walk`` moves to it. NewtonFailure if it fails or is rejected."""
    set_load = system.body.set_load
    if set_load is not None:  # a load the body carries itself (vlab.fe.liquid)
        set_load(t_try)
    if q_target is not None:  # from the new increment
        found = solve_force_controlled(system, system.body.evaluate(walk.current.u), walk.t, q_target,
                                       stepping.newton)
        step = _Step(found.evaluation, found.t, found.record, found.tangent, None)
    else:
        converged_tangent = cache.holds(walk.current)
        step = _substep(system, walk.current, converged_tangent or walk.tangent, walk.t, t_try, stepping,
                        converged_tangent, walk.previous, cache.hierarchy)
    objection = stepping.accept and stepping.accept(step.evaluation, float(step.t))
    if objection:
        raise Rejected(objection, step.record, None)
    walk.previous, walk.current = step.here, step.evaluation
    return step


def _check_restrained(tangent: Tangent, partition: Partition) -> None:
    """Raise SingularSystem if the unloaded K_ff has (numerically) zero eigenvalues: rigid-body
    modes the grips leave free. A factorization may still "succeed" on such a K_ff with round-off
    pivots, and the load, orthogonal to the free modes, would then drive Newton astray with no
    word of the cause. The count reuses the factor (SuperLU's pivots, or two PARDISO solves)."""
    if tangent.Kff is None or len(partition.free) == 0:
        return
    found = factorized_inertia(tangent.factor, tangent.Kff, accurate=False)  # the count only
    if found.zero:
        raise SingularSystem(f"{found.zero} zero eigenvalue(s) of K_ff at rest ({found.method})")


def _finish(history: SolveHistory, start: float, cache: TangentCache, newton_factorizations: int):
    history.factorizations = cache.factorizations + newton_factorizations
    history.amg_setups = cache.amg_setups
    history.seconds = time.perf_counter() - start
    return history


def _tangent_step(system: System, current: Evaluation, tangent: Tangent, du_p: np.ndarray, dt: float):
    """Δu_f = −K_ff⁻¹ (K_fp Δû_p + Δt ∂f/∂t): the grips' move, and the rate of a load the body
    carries itself (the bulge tester's pumped liquid: vlab.fe.liquid), on the current tangent."""
    predicted = -tangent.factor.solve(tangent.Kfp @ du_p)
    load_rate = system.body.load_rate
    if load_rate is not None:
        predicted -= dt * tangent.factor.solve(load_rate(current)[system.free])
    return predicted


def _substep(system: System, current: Evaluation, tangent: Tangent, t0, t1, stepping: Stepping,
             converged_tangent: Tangent | None = None, previous: PathPoint | None = None,
             hierarchy=None) -> _Step:
    """Move the grips from t0 to t1, predict the free DOFs, then iterate to equilibrium.

    The predictor starts from the tangent step v₀ Δt, v₀ = du_f/dt = −K_ff⁻¹ K_fp û_p (the
    current tangent, already factorized), and extrapolates the path through the previous
    converged state (``path_increment``): the cubic when both states' own v are known, else the
    quadratic. Measured on the ISO 527-2 1BA dogbone (10 steps to stretch 1.5), first residual
    of the last step: tangent alone 7.7e-3, quadratic 3.7e-4, cubic 1.9e-5 (Newton iterations
    33 → 28 with the factor reuse of ``solve_equilibrium``). The extrapolation is used only
    - while the load keeps its direction (a reversal in a cyclic test is a kink in the path);
    - up to MAX_EXTRAPOLATION times the last interval (the modulus-window levels are ~1e-4 of a
      load step, and τ³ would amplify their round-off);
    - while its curvature term stays below CURVATURE_TRUST times the tangent step, else the
      quadratic, else the tangent alone: past a buckling point converged states jump between
      neighbouring paths and a polynomial through them predicts nonsense (the imperfect ISO 37
      dumb-bell in compression: a correction of 1.6e3 mm against a tangent step of 0.2 mm; on
      smooth paths the ratio is 0.01–0.1).
    If the prediction inverts an element (large increments near a limit point), it is scaled
    back; the plain grip jump (scale 0) is the last candidate.

    Returns the converged step (its tangent or None, and the path point of t₀)."""
    prescribed, free = system.prescribed, system.free
    dt = t1 - t0
    du_p = system.grip_increment(t0, t1)
    predicted = _tangent_step(system, current, tangent, du_p, dt)
    here = PathPoint(t0, current.u, predicted / dt if converged_tangent is not None and dt else None)
    predicted = _extrapolated(predicted, here, previous, free, dt)
    for scale in (1.0, 0.5, 0.25, 0.0):
        u = current.u.copy()
        u[prescribed] += du_p
        u[free] += scale * predicted
        start = system.body.evaluate(u)
        if start.admissible:
            break
    found = solve_equilibrium(system, start, stepping.newton, converged_tangent, hierarchy)
    return _Step(found.evaluation, t1, found.record, found.tangent, here)


def _extrapolated(linear: np.ndarray, here: PathPoint, previous: PathPoint | None, free: np.ndarray,
                  dt: float) -> np.ndarray:
    """The tangent step ``linear`` (free DOFs, mm) replaced by the cubic, else the quadratic,
    extrapolation of the path through ``previous`` and ``here`` where ``_substep`` trusts it."""
    h = None if previous is None else here.t - previous.t
    if not (h and 0.0 < dt / h <= MAX_EXTRAPOLATION):
        return linear
    exact_slopes = here.velocity is not None and previous.velocity is not None
    limit = CURVATURE_TRUST * np.linalg.norm(linear)
    for v_prev in ((previous.velocity,) if exact_slopes else ()) + (None,):  # cubic, quadratic
        candidate = path_increment(h, dt, previous.u[free], here.u[free], linear / dt, v_prev)
        if np.linalg.norm(candidate - linear) <= limit:
            return candidate
    return linear


def path_increment(h: float, dt: float, u_prev: np.ndarray, u_now: np.ndarray, v_now: np.ndarray,
                   v_prev: np.ndarray | None = None) -> np.ndarray:
    """Δu = u(t₀ + Δt) − u(t₀) of the polynomial through the converged states t₋ = t₀ − h and t₀.

    With a = u₋ − u₀ + v₀ h, τ = Δt / h:  Δu = v₀ Δt + X τ² + Y τ³, where
    X = a, Y = 0 without v₋ (the quadratic matching u₋, u₀, v₀), and X = 3a + (v₋ − v₀) h,
    Y = 2a + (v₋ − v₀) h with it (the cubic matching u and v at both states: exact for a cubic
    path, error O(Δt⁴)). Derivation: u₋ = u₀ − v₀ h + c₂h² − c₃h³ and v₋ = v₀ − 2c₂h + 3c₃h²
    give X = c₂h² and Y = c₃h³."""
    tau = dt / h
    a = u_prev - u_now + v_now * h
    if v_prev is None:
        return v_now * dt + tau**2 * a
    b = (v_prev - v_now) * h
    return v_now * dt + tau**2 * (3.0 * a + b) + tau**3 * (2.0 * a + b)


def _settled(system: System, current: Evaluation, stepping: Stepping) -> Evaluation:
    """Equilibrium under the dead load alone, grips at rest (t = 0)."""
    history = system.body.history
    if history is not None:
        history.begin_increment(0.0)
    settled = solve_equilibrium(system, current, stepping.newton).evaluation
    if history is not None:
        history.commit(settled)
    return settled


def _diagnose(index: int, target: float, attempted: float, failure: NewtonFailure,
              converged: float, u_converged: np.ndarray | None = None) -> Failure:
    ev = failure.evaluation
    inverted = ev is not None and not ev.admissible
    return Failure(
        level=index, t_target=float(target), t_attempted=float(attempted),
        t_converged=float(converged), reason=failure.reason,
        residuals=list(failure.record.residuals),
        min_J=None if ev is None else ev.min_J,
        element=ev.worst[0] if inverted else None,
        quadrature_point=ev.worst[1] if inverted else None, u_converged=u_converged,
    )
