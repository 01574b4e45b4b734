"""Lab instruments. They read a converged state and never write it.

- LoadCell: the reaction force of a moving grip, Σ f_int over the grip's DOFs along its axis (N),
  times ``factor`` (the full specimen's force over the kept part's on a symmetry-reduced model).
- Extensometer: two material points; reads their deformed distance |x_b - x_a| (mm) from the
  finite-element interpolation of u, so the marks follow the material. On a symmetry-reduced
  model a mark behind a cut plane is read at its mirror image and reflected back
  (geometry/symmetry.py).
- ThicknessGauge: a micrometer through a 2D sheet at an in-plane point: the current thickness
  λ₃ t, with λ₃ the out-of-plane stretch of the plane law (vlab.materials.plane) averaged over the
  quadrature points of the element holding the point (weights dx).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.geometry.locate import locate
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
    def __init__(self, space: DisplacementSpace, marks: GaugeMarks, planes: tuple = (), probe=None):
        """``probe``: the interpolation rows of ``reading_points(marks, planes)``, when a caller
        locates the points of several instruments in one search (else located here)."""
        self.marks = marks
        self.length0 = marks.length
        self._planes = planes
        images = [reflection(p, planes) for p in (marks.a, marks.b)]
        self._X = np.array([x for x, _ in images])
        self._signs = [s for _, s in images]
        self._probe = space.probe_matrix(self._X.T) if probe is None else probe
        self._dim = space.dim

    @staticmethod
    def reading_points(marks: GaugeMarks, planes: tuple = ()) -> np.ndarray:
        """(2, dim) points where the marks are read (mirror images on a reduced model), mm."""
        return np.array([reflection(p, planes)[0] for p in (marks.a, marks.b)])

    def length(self, u: np.ndarray) -> float:
        """Current distance between the marks, mm."""
        x = self._X + self._probe @ u.reshape(-1, self._dim)
        a, b = (reflect_back(x[i], self._signs[i], self._planes) for i in (0, 1))
        return float(np.linalg.norm(b - a))

    def strain(self, u: np.ndarray) -> float:
        """Engineering strain (L - L0)/L0 of the gauge length."""
        return self.length(u) / self.length0 - 1.0


def extensometers(space: DisplacementSpace, marks: list[GaugeMarks], planes: tuple = ()) -> list[Extensometer]:
    """Extensometers for several mark pairs, their points located in one probe (the element
    search and inverse mapping dominate building an instrument: ~4 ms per call on small meshes)."""
    points = np.concatenate([Extensometer.reading_points(m, planes) for m in marks])
    rows = space.probe_matrix(points.T).tocsr()
    return [Extensometer(space, m, planes, probe=rows[2 * k:2 * k + 2]) for k, m in enumerate(marks)]


class ThicknessGauge:
    """Reads a sheet's thickness at the in-plane point of ``marks`` (the faces z = 0 and z = t)."""

    def __init__(self, space: DisplacementSpace, material, marks: GaugeMarks):
        self.marks, self.material = marks, material
        self.length0 = marks.length  # the reference thickness t, mm
        point = np.asarray(marks.a[:2], dtype=float)
        self.element = int(locate(space.basis, point[:, None])[0][0])
        self._nodes = space.element_nodes[self.element]
        self._dN = space.dN[self.element]  # (q, a, J)
        self._w = space.dx[self.element] / space.dx[self.element].sum()

    def stretch(self, u: np.ndarray) -> float:
        """λ₃ at the point: dx-weighted mean over the element's quadrature points."""
        ue = u.reshape(-1, 2)[self._nodes]  # (a, i)
        F = np.einsum("ai,qaJ->iJq", ue, self._dN) + np.eye(2)[:, :, None]
        return float(self._w @ self.material.out_of_plane_stretch(F))

    def length(self, u: np.ndarray) -> float:
        """Current thickness λ₃ t, mm."""
        return self.stretch(u) * self.length0

    def strain(self, u: np.ndarray) -> float:
        """Thickness strain λ₃ − 1."""
        return self.stretch(u) - 1.0


class ShearGauge:
    """Shear strain from two gauge marks one above the other (along y) on a free face: the change
    of their x offset over their initial y separation, γ_g = (u_x(b) − u_x(a)) / (Y_b − Y_a) (a
    lab's marks read by video or a clip gauge; equal to γ in a homogeneous simple shear)."""

    def __init__(self, space: DisplacementSpace, marks: GaugeMarks):
        self.marks = marks
        self.height0 = float(marks.b[1] - marks.a[1])
        if self.height0 <= 0:
            raise ValueError("shear gauge marks must be one above the other (b above a along y)")
        self._probe = space.probe_matrix(np.array([marks.a, marks.b]).T)
        self._dim = space.dim

    def strain(self, u: np.ndarray) -> float:
        """γ_g (1)."""
        ux = (self._probe @ u.reshape(-1, self._dim))[:, 0]
        return float(ux[1] - ux[0]) / self.height0
