"""Force control of the moving grip: the crosshead position is an unknown, the force is given.

Under displacement control the grip DOFs follow u_p = t û_p with t prescribed. Under force
control (a creep hold) t becomes an unknown, with the held load as its conjugate: the moving
grip's DOFs stay tied to the single crosshead coordinate t (they move together, as a rigid
crosshead does), and the generalized force conjugate to t is

    Q(u) = ∂W/∂t = ûᵀ f_int(u)   (N·mm; = û_m × grip force, û_m the grip's travel at t = 1).

Equilibrium at a held force F* is the stationary point of the total potential

    Π(u_f, t) = W(u_f, t û_p) − Q* t,     Q* = û_m F*,

solved by Newton on the bordered system (g = K û, all with the current tangent K):

    [ K_ff    g_f ] [Δu_f]     [ r_f = f_int,f   ]
    [ g_fᵀ   ûᵀg  ] [ Δt ] = − [ r_t = Q − Q*    ]

by block elimination with the one factorization of K_ff: a = −K_ff⁻¹ r_f, b = K_ff⁻¹ g_f,
Δt = −(r_t + g_f·a)/(ûᵀg − g_f·b), Δu_f = a − b Δt. The step length is the one of
displacement-controlled Newton (vlab.fe.line_search: the watchdog on the merit function, here
Π, with backtracking; J ≤ 0 inadmissible), applied to the bordered unknowns (u_f, s = t û_m):
their residual (r_f, r_t/û_m) is in N, its slope along (Δu_f, Δs) is r_f·Δu_f + r_t Δt. A body
with element unknowns of its own (the mixed body's θ, vlab.fe.mixed) moves them with their Newton
update along the whole step (grip travel included), so force control runs the three-field
iteration as displacement control does, and converges also needs max|Π_e v − θ| ≤ rtol. The
residual is measured as ‖(r_f, r_t/û_m)‖ (N) against the same force scale as
displacement-controlled Newton.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.line_search import Watchdog, norm
from vlab.fe.linsolve import SingularSystem, factorize
from vlab.fe.newton import NewtonFailure, NewtonOptions, NewtonRecord, Tangent
from vlab.fe.problem import Evaluation
from vlab.fe.system import System


def generalized_force(ev: Evaluation, u_hat: np.ndarray) -> float:
    """Q = ûᵀ f_int (N·mm), the load conjugate to the load parameter t."""
    return float(u_hat @ ev.f_int)


@dataclass(frozen=True)
class ForceControlled:
    """A converged force-controlled solve: the state, its load parameter t, the record, the last
    tangent factorized."""

    evaluation: Evaluation
    t: float
    record: NewtonRecord
    tangent: Tangent | None


class _BorderedState:
    """The body's state ``ev`` at load parameter ``t`` seen as a state of the bordered unknowns
    (u, s = t û_m): merit W = Π = W − Q* t (mJ), residual f_int = (f_int, (Q − Q*)/û_m) (N)."""

    def __init__(self, ev: Evaluation, t: float, q_target: float, u_hat: np.ndarray, travel: float):
        self.ev, self.t = ev, t
        self.u = np.append(ev.u, t * travel)
        self.W = ev.W - q_target * t
        self.r_t = generalized_force(ev, u_hat) - q_target if ev.admissible else np.inf
        self.f_int = np.append(ev.f_int, self.r_t / travel) if ev.admissible else None
        # the line search moves a state that carries element unknowns by ``advance`` (θ with u);
        # the bordered state always moves that way (t with u): not None
        self.volume_change = ev.volume_change, t

    @property
    def admissible(self) -> bool:
        return self.f_int is not None


class _BorderedBody:
    """The body under force control, for vlab.fe.line_search: a step (Δu, Δs) moves the grip DOFs
    by (Δs/û_m) û with the free ones, and the body's own element unknowns with their update."""

    def __init__(self, body, u_hat: np.ndarray, q_target: float, travel: float):
        self.body, self.u_hat, self.q_target, self.travel = body, u_hat, q_target, travel

    def state(self, ev: Evaluation, t: float) -> _BorderedState:
        return _BorderedState(ev, t, self.q_target, self.u_hat, self.travel)

    def advance(self, state: _BorderedState, step: np.ndarray, alpha: float) -> _BorderedState:
        dt = step[-1] / self.travel
        du = step[:-1] + dt * self.u_hat
        if self.body.advance is not None and state.ev.volume_change is not None:  # declared: vlab.fe.body
            inner = self.body.advance(state.ev, du, alpha)
        else:
            inner = self.body.evaluate(state.ev.u + alpha * du)
        return self.state(inner, state.t + alpha * dt)


def _bordered_correction(body, partition, ev: Evaluation, r_t: float, u_hat: np.ndarray):
    """(Tangent, Δu_f, Δt) of the bordered Newton system at ``ev`` (module docstring)."""
    free = partition.free
    try:
        K = body.stiffness(ev)
        Kff, Kfp = partition.blocks(K)
        tangent = Tangent(factorize(Kff), Kfp)
        g = K @ u_hat
        a, b = tangent.factor.solve(-ev.f_int[free]), tangent.factor.solve(g[free])
        schur = float(u_hat @ g - g[free] @ b)
        if not schur > 0.0:
            raise SingularSystem(f"the crosshead stiffness under force control is {schur:.3g} N·mm "
                                 "(a load limit point: the held force cannot be carried)")
    except SingularSystem as exc:
        raise NewtonFailure(f"singular tangent under force control: {exc}", NewtonRecord(), ev) from exc
    dt = -(r_t + float(g[free] @ a)) / schur
    return tangent, a - b * dt, dt


def solve_force_controlled(system: System, start: Evaluation, t0: float, Q_target: float,
                           options: NewtonOptions) -> ForceControlled:
    """Newton for (u_f, t) at the held generalized force ``Q_target`` from ``start`` (at t0)."""
    body, partition, u_hat = system.body, system.partition, system.u_hat
    record = NewtonRecord()
    force_floor, length = system.scales
    free, presc = partition.free, partition.prescribed
    travel = float(np.max(np.abs(u_hat)))  # û_m, mm
    if not start.admissible:
        record.reason = f"the held state is inadmissible (min J = {start.min_J:.3g})"
        raise NewtonFailure(record.reason, record, start)
    bordered = _BorderedBody(body, u_hat, Q_target, travel)
    state, tangent = bordered.state(start, float(t0)), None
    unknowns = np.append(free, len(start.u))  # free DOFs, then s = t û_m
    watchdog = Watchdog(options.watchdog)
    for k in range(options.max_iterations + 1):
        ev = state.ev
        scale = max(force_floor, norm(ev.f_int[presc]))
        record.residuals.append(norm(state.f_int[unknowns]) / scale)
        if (record.residuals[-1] <= options.rtol and (k == 0 or record.updates[-1] <= options.utol)
                and ev.constraint <= options.rtol):
            record.converged = True
            return ForceControlled(ev, state.t, record, tangent)
        if k == options.max_iterations:
            break
        try:
            tangent, du, dt = _bordered_correction(body, partition, ev, state.r_t, u_hat)
        except NewtonFailure as exc:
            record.reason = exc.reason
            raise NewtonFailure(record.reason, record, ev) from exc
        state, alpha, step = watchdog.advance(bordered, unknowns, state, np.append(du, dt * travel),
                                              options, record)
        if state is None:
            record.reason = "line search found no admissible decrease under force control"
            raise NewtonFailure(record.reason, record, alpha.ev if isinstance(alpha, _BorderedState) else alpha)
        record.step_lengths.append(alpha)
        record.updates.append(alpha * float(np.max(np.abs(step), initial=0.0)) / length)
    record.reason = f"no convergence in {options.max_iterations} iterations under force control"
    raise NewtonFailure(record.reason, record, state.ev)
