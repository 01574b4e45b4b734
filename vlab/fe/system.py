"""The system being solved: one value object instead of the (body, partition, u_hat, scales)
clump that Newton, force control and the load stepping all took.

    body       the discretised body (vlab.fe.body.Body)
    partition  free / prescribed DOFs (vlab.fe.assembly.Partition)
    u_hat      prescribed displacements at load parameter t = 1, mm (all DOFs; zero on the free
               ones); None where the caller moves the grips itself (a plain equilibrium solve)
    scales     (force floor, N; length, mm): Newton's residual is |r_f| / max(floor, |f_p|), its
               update criterion max|Δu| / length
    path       None (u_p(t) = t · û_p), or u_p(t) itself where the grips do not move in proportion
               (a rotating grip; vlab.loading.grips.GripLoading.path)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np

if TYPE_CHECKING:
    from vlab.fe.assembly import Partition
    from vlab.fe.body import Body

__all__ = ["System"]


@dataclass(frozen=True)
class System:
    body: "Body"
    partition: "Partition"
    u_hat: np.ndarray | None
    scales: tuple[float, float]
    path: Callable[[float], np.ndarray] | None = None

    def grip_increment(self, t0: float, t1: float) -> np.ndarray:
        """u_p(t₁) − u_p(t₀) on the prescribed DOFs (mm)."""
        if self.path is None:
            return (t1 - t0) * self.u_hat[self.partition.prescribed]
        return (self.path(t1) - self.path(t0))[self.partition.prescribed]

    @property
    def free(self) -> np.ndarray:
        return self.partition.free

    @property
    def prescribed(self) -> np.ndarray:
        return self.partition.prescribed
