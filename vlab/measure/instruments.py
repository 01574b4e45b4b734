"""Lab instruments. They read a converged state and never write it.

- LoadCell: the reaction force of a moving grip, Σ f_int over the grip's DOFs along its axis (N).
- Extensometer: two material points; reads their deformed distance |x_b - x_a| (mm) from the
  finite-element interpolation of u, so the marks follow the material.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.space import DisplacementSpace
from vlab.geometry.specimen import GaugeMarks


@dataclass(frozen=True)
class LoadCell:
    dofs: np.ndarray

    def read(self, f_int: np.ndarray) -> float:
        """Axial grip force, N (positive in tension)."""
        return float(f_int[self.dofs].sum())


class Extensometer:
    def __init__(self, space: DisplacementSpace, marks: GaugeMarks):
        self.marks = marks
        self.length0 = marks.length
        self._X = np.array([marks.a, marks.b], dtype=float)
        self._probe = space.probe_matrix(self._X.T)

    def length(self, u: np.ndarray) -> float:
        """Current distance between the marks, mm."""
        x = self._X + self._probe @ u.reshape(-1, 3)
        return float(np.linalg.norm(x[1] - x[0]))

    def strain(self, u: np.ndarray) -> float:
        """Engineering strain (L - L0)/L0 of the gauge length."""
        return self.length(u) / self.length0 - 1.0
