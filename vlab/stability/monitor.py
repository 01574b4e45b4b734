"""After every converged load level: is the state stable, and has the load passed a limit point?

Newton converging only means the state is stationary. It is a stable equilibrium (a local minimum
of the total energy W) iff the tangent on the free DOFs K_ff is positive definite, so the monitor
counts the negative (and zero) eigenvalues of K_ff by its inertia (:mod:`vlab.fe.inertia`).

Under displacement control a softening material (St. Venant–Kirchhoff in compression: the nominal
stress of a free block, μλ(λ²−1)-like, peaks at stretch 1/√3) can still give a positive definite
K_ff past its load maximum, so the monitor also watches the load cells: a load limit point is
passed when |force| on a loaded axis falls while its grip keeps moving away from 1,
    s_a (f_a(t_k) − f_a(t_{k−1})) < −tol · |f_a(t_{k−1})|,   s_a = sign(λ_a − 1).
Either event rejects the level (:class:`LevelRejected`): it is recorded with its inertia, but its
numbers never enter the curve, and the test stops with "no admissible state beyond stretch …".
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from vlab.fe.assembly import Partition
from vlab.fe.inertia import inertia
from vlab.fe.problem import HyperelasticBody
from vlab.fe.stepping import Level, LevelRejected

LIMIT_TOL = 1e-9


@dataclass(frozen=True)
class LevelStability:
    """Stability record of one converged level (``accepted`` False if it stopped the test)."""

    t: float
    stretch: list[float]
    negative_eigenvalues: int | None
    zero_eigenvalues: int | None
    inertia_method: str
    forces: list[float]
    limit_point: bool
    accepted: bool

    def as_dict(self) -> dict:
        return asdict(self)


class StabilityMonitor:
    """Callable observer: ``monitor(level)`` records a LevelStability or raises LevelRejected."""

    def __init__(self, body: HyperelasticBody, partition: Partition, moving_dofs: dict[int, np.ndarray],
                 target_stretch: tuple[float, ...], model: str):
        self.body, self.partition = body, partition
        self.moving = {a: np.asarray(d) for a, d in moving_dofs.items()}
        self.target = target_stretch
        self.model = model
        self.records: list[LevelStability] = []

    def stretch_at(self, t: float) -> list[float]:
        return [1.0 + t * (s - 1.0) for s in self.target]

    def __call__(self, level: Level) -> None:
        ev = level.evaluation
        Kff, _ = self.partition.blocks(self.body.stiffness(ev))
        found = inertia(Kff)
        forces = [float(ev.f_int[self.moving[a]].sum()) for a in range(len(self.target))]
        limit_axis = self._limit_axis(forces)
        unstable = bool(found.negative) or bool(found.zero)
        record = LevelStability(float(level.t), self.stretch_at(level.t), found.negative, found.zero,
                                found.method, forces, limit_axis is not None,
                                accepted=not unstable and limit_axis is None)
        self.records.append(record)
        if unstable:
            raise LevelRejected(self._instability_message(record))
        if limit_axis is not None:
            raise LevelRejected(self._limit_message(record, limit_axis))

    def _last_accepted(self) -> LevelStability | None:
        return next((r for r in reversed(self.records) if r.accepted), None)

    def _limit_axis(self, forces: list[float]) -> int | None:
        last = self._last_accepted()
        if last is None:
            return None
        for a, (f_new, f_old) in enumerate(zip(forces, last.forces)):
            sign = np.sign(self.target[a] - 1.0)
            if sign != 0 and sign * (f_new - f_old) < -LIMIT_TOL * abs(f_old):
                return a
        return None

    def _previous_stretch(self) -> str:
        last = self._last_accepted()
        return _fmt(last.stretch if last else self.stretch_at(0.0))

    def _instability_message(self, r: LevelStability) -> str:
        what = (f"{r.negative_eigenvalues} negative eigenvalue(s)" if r.negative_eigenvalues
                else f"{r.zero_eigenvalues} zero eigenvalue(s)")
        return (f"no admissible state beyond stretch {self._previous_stretch()}: loss of stability "
                f"at stretch {_fmt(r.stretch)} — the tangent on the free DOFs has {what}, so the "
                f"converged state is not an energy minimum ({self.model}; a bifurcation such as "
                f"buckling or loss of ellipticity)")

    def _limit_message(self, r: LevelStability, axis: int) -> str:
        advice = (" (St. Venant–Kirchhoff softens in compression, limit point at stretch 1/√3 "
                  "≈ 0.577 for a free block; stvk-volumetric and neo-hookean carry on)"
                  if self.model == "stvk" else "")
        return (f"no admissible state beyond stretch {self._previous_stretch()}: load limit point — "
                f"|force| along {'xy'[axis]} peaked and fell at stretch {_fmt(r.stretch)}{advice}")


def _fmt(stretch: list[float]) -> str:
    return ", ".join(f"{s:.4g}" for s in stretch) if len(stretch) > 1 else f"{stretch[0]:.4g}"
