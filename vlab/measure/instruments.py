"""Lab instruments. They read a converged state and never write it.

- LoadCell: the reaction force of a moving grip, Σ f_int over the grip's DOFs along its axis (N),
  times ``factor`` (the full specimen's force over the kept part's on a symmetry-reduced model).
- Extensometer: two material points; reads their deformed distance |x_b - x_a| (mm) from the
  finite-element interpolation of u, so the marks follow the material. On a symmetry-reduced
  model a mark behind a cut plane is read at its mirror image and reflected back
  (geometry/symmetry.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.space import DisplacementSpace
from vlab.geometry.specimen import GaugeMarks
from vlab.geometry.symmetry import reflect_back, reflection


@dataclass(frozen=True)
class LoadCell:
    dofs: np.ndarray
    factor: float = 1.0

    def read(self, f_int: np.ndarray) -> float:
        """Axial grip force, N (positive in tension)."""
        return self.factor * float(f_int[self.dofs].sum())


class Extensometer:
    def __init__(self, space: DisplacementSpace, marks: GaugeMarks, planes: tuple = ()):
        self.marks = marks
        self.length0 = marks.length
        self._planes = planes
        images = [reflection(p, planes) for p in (marks.a, marks.b)]
        self._X = np.array([x for x, _ in images])
        self._signs = [s for _, s in images]
        self._probe = space.probe_matrix(self._X.T)

    def length(self, u: np.ndarray) -> float:
        """Current distance between the marks, mm."""
        x = self._X + self._probe @ u.reshape(-1, 3)
        a, b = (reflect_back(x[i], self._signs[i], self._planes) for i in (0, 1))
        return float(np.linalg.norm(b - a))

    def strain(self, u: np.ndarray) -> float:
        """Engineering strain (L - L0)/L0 of the gauge length."""
        return self.length(u) / self.length0 - 1.0
