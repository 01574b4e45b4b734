"""Step length for Newton's method on the energy W: backtracking (Armijo) and the watchdog.

Used by vlab.fe.newton. A trial state u + αΔu is evaluated by the body, or, for a body with
element unknowns of its own (the mixed body's θ), advanced with their Newton update. A trial with
J <= 0 anywhere is inadmissible (W = +inf). Accepted: sufficient decrease
    W(u + αΔu) <= W(u) + c α rᵀΔu,
or (close to the solution W changes by less than its round-off) ‖r‖ cut by the same factor.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from vlab.fe.problem import Evaluation

if TYPE_CHECKING:
    from vlab.fe.newton import NewtonOptions, NewtonRecord


def dot(a: np.ndarray, b: np.ndarray) -> float:
    """aᵀb without BLAS: a BLAS level-1 call wakes its thread pool, which on a loaded machine
    cost ~10 ms per call (measured), more than the whole residual evaluation of a small mesh."""
    return float(np.einsum("i,i->", a, b))


def norm(a: np.ndarray) -> float:
    """‖a‖₂; where aᵀa under- or overflows (forces ~1e-160 N or ~1e160 N) the scaled norm,
    so that a residual is never read as 0 (or inf) for want of exponent range."""
    n = math.sqrt(dot(a, a))
    if (n < 1e-150 or not math.isfinite(n)) and a.size:
        peak = float(np.max(np.abs(a)))
        if peak > 0.0 and math.isfinite(peak):
            return peak * math.sqrt(dot(a / peak, a / peak))
    return n


class Watchdog:
    """Nonmonotone acceptance of full Newton steps: the watchdog technique (Chamberlain, Powell,
    Lemaréchal & Pedersen, Math. Prog. Study 16, 1982) on the energy W.

    Near incompressibility a full Newton step raises W although it is a good step: the step is
    linear in Δu while the volume change it makes is quadratic (a rotation Δu = ω × x changes
    J by O(ω²)), and the volumetric energy multiplies that by κ ≈ 5000 μ at ν = 0.4999, so
    W(u + Δu) > W(u) and so does ‖r‖. Backtracking then halves the step and Newton crawls
    (Cook's membrane ν = 0.4999 Q1/P0 8 × 8: 7 iterations a step, α = ½ first; with full steps
    4-5, as in FElupe and deal.II, which take full steps always). So from a *reference* state
    (W_r, slope s_r = r_rᵀΔu_r, ‖r_r‖) the full step is taken even without sufficient
    decrease, up to ``allowance`` steps in a row; the sequence ends as soon as a state satisfies
    the sufficient-decrease test against the reference,
        W ≤ W_r + c s_r   or   ‖r‖ ≤ (1 − c) ‖r_r‖,
    and if none has after ``allowance`` steps, the iteration returns to the reference state and
    backtracks along its direction as the monotone line search would (global convergence is
    kept: at most ``allowance`` wasted steps per return). Inadmissible trials (J ≤ 0) are never
    accepted, and a sequence starts only while ‖r‖ > chord_band · rtol: below, W and ‖r‖ change
    by round-off and a full step that does not decrease them would be taken again and again
    (a P2 tet block at rtol 1e-12 stalled at 6e-11 for 25 iterations). ``allowance`` = 0 is the
    monotone line search."""

    def __init__(self, allowance: int):
        self.allowance = allowance
        self.reference: tuple | None = None  # (evaluation, direction, slope, ‖r‖)
        self.relaxed = 0

    def advance(self, body, free, ev: Evaluation, du: np.ndarray, options: NewtonOptions,
                record: NewtonRecord):
        """(accepted evaluation or None, α, the direction α refers to)."""
        slope, r0 = dot(ev.f_int[free], du), norm(ev.f_int[free])
        trial = _trial(body, free, ev, du, 1.0)
        ref = self.reference or (ev, du, slope, r0)
        if trial.admissible and _sufficient(trial, ref[0].W, ref[2], ref[3], 1.0, free, options):
            self.reference = None
            return trial, 1.0, du
        if self.reference is not None:
            may_relax = self.relaxed < self.allowance
        else:  # near rtol W and ‖r‖ stall at round-off: monotone there (a relaxed step would loop)
            may_relax = self.allowance > 0 and record.residuals[-1] > options.chord_band * options.rtol
        if trial.admissible and may_relax:
            if self.reference is None:
                self.reference, self.relaxed = ref, 0
            self.relaxed += 1
            record.relaxed += 1
            return trial, 1.0, du
        if self.reference is not None:  # the relaxed steps did not pay: back to the reference
            ev, du = self.reference[0], self.reference[1]
            self.reference = None
            record.returns += 1
            accepted, alpha = _line_search(body, free, ev, du, options, 0.5)
        else:
            accepted, alpha = _line_search(body, free, ev, du, options, 0.5, trial)
        return accepted, alpha, du


def _trial(body, free: np.ndarray, ev: Evaluation, du: np.ndarray, alpha: float) -> Evaluation:
    """The state u + αΔu; a body with element unknowns of its own (the mixed body's θ) moves
    them with their Newton update (``body.advance``) where the state carries them."""
    step = np.zeros_like(ev.u)
    step[free] = du
    if body.advance is not None and ev.volume_change is not None:  # declared: vlab.fe.body
        return body.advance(ev, step, alpha)
    return body.evaluate(ev.u + alpha * step)


def _sufficient(trial: Evaluation, W0: float, slope: float, r0: float, alpha: float,
                free: np.ndarray, options: NewtonOptions) -> bool:
    """Armijo on W, or (W changes by less than its round-off near the solution) ‖r‖ cut as much."""
    c = options.sufficient_decrease
    return trial.W <= W0 + c * alpha * slope or norm(trial.f_int[free]) <= (1.0 - c * alpha) * r0


def _line_search(body, free: np.ndarray, ev: Evaluation, du: np.ndarray,
                 options: NewtonOptions, alpha: float = 1.0, last: Evaluation | None = None):
    """Backtracking on W from step ``alpha`` (halving; ``last``: the trial at 2α, if made);
    returns (accepted evaluation, α) or (None, last inadmissible trial)."""
    slope = dot(ev.f_int[free], du)
    r0 = norm(ev.f_int[free])
    tries = options.max_backtracks - int(round(math.log2(1.0 / alpha)))
    for _ in range(tries):
        trial = _trial(body, free, ev, du, alpha)
        if trial.admissible and _sufficient(trial, ev.W, slope, r0, alpha, free, options):
            return trial, alpha
        last = trial
        alpha *= 0.5
    return None, last
