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
Δt = −(r_t + g_f·a)/(ûᵀg − g_f·b), Δu_f = a − b Δt. The line search is the energy line search
on Π (J ≤ 0 inadmissible). The residual is measured as ‖(r_f, r_t/û_m)‖ (N) against the same
force scale as displacement-controlled Newton.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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


def solve_force_controlled(system: System, start: Evaluation, t0: float, Q_target: float,
                           options: NewtonOptions) -> ForceControlled:
    """Newton for (u_f, t) at the held generalized force ``Q_target`` from ``start`` (at t0)."""
    body, partition, u_hat = system.body, system.partition, system.u_hat
    record = NewtonRecord()
    force_floor, length = system.scales
    free, presc = partition.free, partition.prescribed
    travel = float(np.max(np.abs(u_hat)))  # û_m, mm
    ev, t, tangent = start, float(t0), None
    if not ev.admissible:
        record.reason = f"the held state is inadmissible (min J = {ev.min_J:.3g})"
        raise NewtonFailure(record.reason, record, ev)
    for k in range(options.max_iterations + 1):
        r_f, r_t = ev.f_int[free], generalized_force(ev, u_hat) - Q_target
        scale = max(force_floor, float(np.linalg.norm(ev.f_int[presc])))
        record.residuals.append(float(np.hypot(np.linalg.norm(r_f), r_t / travel)) / scale)
        if record.residuals[-1] <= options.rtol and (k == 0 or record.updates[-1] <= options.utol):
            record.converged = True
            return ForceControlled(ev, t, record, tangent)
        if k == options.max_iterations:
            break
        try:
            K = body.stiffness(ev)
            Kff, Kfp = partition.blocks(K)
            tangent = Tangent(factorize(Kff), Kfp)
            g = K @ u_hat
            a, b = tangent.factor.solve(-r_f), tangent.factor.solve(g[free])
            schur = float(u_hat @ g - g[free] @ b)
            if not schur > 0.0:
                raise SingularSystem(f"the crosshead stiffness under force control is {schur:.3g} N·mm "
                                     "(a load limit point: the held force cannot be carried)")
        except SingularSystem as exc:
            record.reason = f"singular tangent under force control: {exc}"
            raise NewtonFailure(record.reason, record, ev) from exc
        dt = -(r_t + float(g[free] @ a)) / schur
        du = a - b * dt
        ev_new, t_new, alpha = _line_search(body, free, ev, t, du, dt, u_hat, Q_target, r_t, options)
        if ev_new is None:
            record.reason = "line search found no admissible decrease under force control"
            raise NewtonFailure(record.reason, record, alpha)
        ev, t = ev_new, t_new
        record.step_lengths.append(alpha)
        step = max(float(np.max(np.abs(du), initial=0.0)), abs(dt) * travel)
        record.updates.append(alpha * step / length)
    record.reason = f"no convergence in {options.max_iterations} iterations under force control"
    raise NewtonFailure(record.reason, record, ev)


def _line_search(body, free, ev, t, du, dt, u_hat, Q_target, r_t, options):
    """Backtracking on Π = W − Q* t; returns (evaluation, t, α) or (None, None, last trial)."""
    slope = float(ev.f_int[free] @ du) + r_t * dt
    travel = float(np.max(np.abs(u_hat)))
    r0 = float(np.hypot(np.linalg.norm(ev.f_int[free]), r_t / travel))
    pi0 = ev.W - Q_target * t
    alpha, last = 1.0, None
    for _ in range(options.max_backtracks):
        u = ev.u + alpha * dt * u_hat
        u[free] += alpha * du
        trial = body.evaluate(u)
        if trial.admissible:
            t_trial = t + alpha * dt
            decrease = trial.W - Q_target * t_trial <= pi0 + options.sufficient_decrease * alpha * slope
            rn = float(np.hypot(np.linalg.norm(trial.f_int[free]),
                                (generalized_force(trial, u_hat) - Q_target) / travel))
            if decrease or rn <= (1.0 - options.sufficient_decrease * alpha) * r0:
                return trial, t_trial, alpha
        last = trial
        alpha *= 0.5
    return None, None, last
