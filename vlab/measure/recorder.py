"""Records the test like a testing machine: one row per converged load level.

Per loaded axis (0 = x, 1 = y) it logs the grip (crosshead) stretch, the load-cell force and the
extensometer strain; across the gauge centre it logs the transverse (width) strain and the
thickness strain (on a 2D sheet from the plane law's out-of-plane stretch λ₃, which needs the
``material``). Stress measures derive from those readings:
    engineering stress  s = force / A0                          (MPa)
    true strain         e = ln(1 + extensometer strain)
    true stress         σ = force / A, A = A0 (1 + ε_w)(1 + ε_t) for uniaxial, A0_axis (1 + ε_other)(1 + ε_t) biaxial
On a cruciform it also logs the centre averages of stress and strain from the FE field
(measure/centre_stress.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vlab.fe.space import DisplacementSpace
from vlab.fe.stepping import Level
from vlab.geometry.specimen import Specimen
from vlab.measure.instruments import LoadCell, ThicknessGauge, extensometers


@dataclass
class Curve:
    """Columns of the test record; every list has one entry per recorded level."""

    t: list[float] = field(default_factory=list)
    stretch: dict[int, list[float]] = field(default_factory=dict)
    force: dict[int, list[float]] = field(default_factory=dict)
    strain: dict[int, list[float]] = field(default_factory=dict)
    transverse_strain: list[float] = field(default_factory=list)
    thickness_strain: list[float] = field(default_factory=list)
    area0: dict[int, float] = field(default_factory=dict)
    time: list[float] = field(default_factory=list)  # s, physical time of each level (timed tests only)
    centre: dict[str, list[float]] = field(default_factory=dict)  # FE centre averages (cruciform)

    @property
    def axes(self) -> list[int]:
        return sorted(self.stretch)

    def column(self, name: str, axis: int = 0) -> np.ndarray:
        """Derived column: engineering/true stress and strain for ``axis``."""
        F, eps = np.array(self.force[axis]), np.array(self.strain[axis])
        if name == "stress":
            return F / self.area0[axis]
        if name == "true_strain":
            return np.log1p(eps)
        if name == "true_stress":
            lateral = (np.array(self.transverse_strain) if len(self.axes) == 1
                       else np.array(self.strain[1 - axis]))
            return F / (self.area0[axis] * (1 + lateral) * (1 + np.array(self.thickness_strain)))
        raise KeyError(name)


class Recorder:
    """Observer hooked after every converged level; reads the instruments into a Curve."""

    def __init__(self, space: DisplacementSpace, specimen: Specimen, stretch: tuple[float, ...],
                 moving_dofs: dict[int, np.ndarray], material=None, centre=None):
        self.centre = centre  # CentreStressProbe or None
        self.axes = list(range(len(stretch)))
        self.target = stretch
        planes = specimen.symmetry
        self.load_cells = {a: LoadCell(moving_dofs[a], specimen.force_factor(a)) for a in self.axes}
        marks = [specimen.extensometers[a] for a in self.axes] + [specimen.transverse[0]]
        if space.dim == 3:
            marks.append(specimen.thickness)
        found = extensometers(space, marks, planes)
        self.extensometers = dict(zip(self.axes, found))
        self.width = found[len(self.axes)]
        self.thickness = (ThicknessGauge(space, material, specimen.thickness) if space.dim == 2
                          else found[-1])
        self.curve = Curve(area0={a: specimen.area0[a] for a in self.axes})
        for a in self.axes:
            self.curve.stretch[a], self.curve.force[a], self.curve.strain[a] = [], [], []

    def __call__(self, level: Level) -> None:
        u, f_int = level.evaluation.u, level.evaluation.f_int
        c = self.curve
        c.t.append(level.t)
        if level.time is not None:
            c.time.append(level.time)
        for a in self.axes:
            c.stretch[a].append(1.0 + level.t * (self.target[a] - 1.0))
            c.force[a].append(self.load_cells[a].read(f_int))
            c.strain[a].append(self.extensometers[a].strain(u))
        if self.centre is not None:
            for key, value in self.centre.read(level.evaluation.F).items():
                c.centre.setdefault(key, []).append(value)
        c.transverse_strain.append(self.width.strain(u))
        c.thickness_strain.append(self.thickness.strain(u))
