"""Dead-load studies (Cook's membrane, deal.II step-44's block): a body plus a fixed external
force, ramped in equal load steps and minimised by vlab's Newton solver.

    Π(u) = W(u) − t f_extᵀu,   force f_int − t f_ext,   t = 1/n, 2/n, …, 1.

The lab's scenes prescribe grip displacements; these benchmark problems prescribe tractions, so
the load enters here as a dead external force. A load step whose Newton solve fails is retried
with half the increment (the count of such cutbacks is kept, with every Newton record).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from vlab.fe.assembly import Partition
from vlab.fe.newton import NewtonFailure, NewtonOptions, NewtonRecord, solve_equilibrium
from vlab.fe.system import System


class DeadLoad:
    """A body plus a dead external force: Π(u) = W(u) − f_extᵀu (mJ), force f_int − f_ext (N)."""

    def __init__(self, body, f_ext: np.ndarray):
        self.body, self.f_ext = body, f_ext
        self.space, self.pattern, self.material = body.space, body.pattern, body.material
        if body.advance is None:
            self.advance = None  # no element unknowns: Newton evaluates u + αΔu directly

    def evaluate(self, u: np.ndarray):
        return self._loaded(self.body.evaluate(u), u)

    def advance(self, evaluation, du: np.ndarray, alpha: float):
        """The body's own Newton update (the mixed body's θ), with the dead load added."""
        return self._loaded(self.body.advance(evaluation, du, alpha), evaluation.u + alpha * du)

    def _loaded(self, ev, u: np.ndarray):
        if not ev.admissible:
            return ev
        return dataclasses.replace(ev, W=ev.W - float(self.f_ext @ u), f_int=ev.f_int - self.f_ext)

    def stiffness(self, evaluation):
        return self.body.stiffness(evaluation)


@dataclass
class Ramp:
    """Result of a ramp: final u (mm), the Newton records of the converged steps (in order) and
    of the failed attempts, and why it stopped early ('' if it reached t = 1)."""

    u: np.ndarray
    steps: list[NewtonRecord] = field(default_factory=list)
    failed: list[NewtonRecord] = field(default_factory=list)
    failure: str = ""

    @property
    def iterations(self) -> int:
        return sum(r.iterations for r in self.steps + self.failed)

    @property
    def per_step(self) -> list[int]:
        return [r.iterations for r in self.steps]


def ramp(body, partition: Partition, f_total: np.ndarray, steps: int, options: NewtonOptions,
         length: float, min_step: float = 1e-3) -> Ramp:
    """Equal load increments 1/steps of ``f_total`` (N) from u = 0, halved on a Newton failure
    down to ``min_step``; ``length`` (mm) scales the update criterion."""
    result = Ramp(np.zeros(body.space.n_dofs))
    load, step = 0.0, 1.0 / steps
    while load < 1.0 - 1e-12:
        target = min(1.0, load + step)
        loaded = DeadLoad(body, target * f_total)
        try:
            found = solve_equilibrium(System(loaded, partition, None, (1e-12, length)),
                                      loaded.evaluate(result.u), options)
            ev, record = found.evaluation, found.record
        except NewtonFailure as exc:
            result.failed.append(exc.record)
            step /= 2.0
            if step < min_step:
                result.failure = f"load factor {target:.4g}: {exc.reason}"
                return result
            continue
        result.u, load = ev.u, target
        result.steps.append(record)
    return result
