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
from vlab.measure.instruments import LoadCell, ThicknessGauge


@dataclass
class Curve:
    """Columns of the test record; every list has one entry per recorded level."""

    t: list[float] = field(default_factory=list)
    # per load cell (axis): the control value (grip stretch; simple shear: the plate-travel shear γ),
    # the force (N) and the strain gauge (extensometer strain; simple shear: gauge-mark shear)
    stretch: dict[int, list[float]] = field(default_factory=dict)
    force: dict[int, list[float]] = field(default_factory=dict)
    strain: dict[int, list[float]] = field(default_factory=dict)
    transverse_strain: list[float] = field(default_factory=list)
    thickness_strain: list[float] = field(default_factory=list)
    area0: dict[int, float] = field(default_factory=dict)
    time: list[float] = field(default_factory=list)  # s, physical time of each level (timed tests only)
    centre: dict[str, list[float]] = field(default_factory=dict)  # FE centre averages (cruciform)
    kind: str = "uniaxial"  # the test kind (vlab.loading.kinds) whose record this is
    extra: dict[str, list[float]] = field(default_factory=dict)  # the kind's other readings (normal force, ...)
    slip: float = 0.0  # 1/N: the grips' slip compliance over the grip separation, C/L_grip (test.grip_slip)

    @property
    def axes(self) -> list[int]:
        return sorted(self.stretch)

    def crosshead_strain(self, axis: int = 0) -> np.ndarray:
        """What the crosshead reads, as strain: (Δ + C F)/L_grip = λ_grip − 1 + (C/L_grip) F, the
        clamps' travel plus the specimen's slip in the grips, C F (C the slip compliance, mm/N,
        test.grip_slip; the slip grows with the force, so the crosshead modulus falls to
        E_c/(1 + C k), k = F/Δ the specimen's stiffness, and the extensometer does not see it)."""
        return np.array(self.stretch[axis]) - 1.0 + self.slip * np.array(self.force[axis])

    def column(self, name: str, axis: int = 0) -> np.ndarray:
        """Derived column: engineering/true stress and strain for ``axis``."""
        F, eps = np.array(self.force[axis]), np.array(self.strain[axis])
        if name == "stress":
            return F / self.area0[axis]
        if name == "true_strain":
            return np.log1p(eps)
        if name == "true_stress":
            other = self.strain.get(1 - axis)  # a biaxial test's other axis, else the width gauge
            lateral = np.array(self.transverse_strain if other is None else other)
            return F / (self.area0[axis] * (1 + lateral) * (1 + np.array(self.thickness_strain)))
        raise KeyError(name)


class Recorder:
    """Observer hooked after every converged level; reads the instruments into a Curve.

    The test kind (vlab.loading.kinds) decides which load cells (``kind.axes``), strain gauges and
    other readers there are, the control value of each axis at load parameter t (grip stretch, or
    the amount of shear) and each load cell's reference area."""

    def __init__(self, space: DisplacementSpace, specimen: Specimen, kind, targets: tuple[float, ...],
                 loading, material=None, centre=None):
        self.centre = centre  # CentreStressProbe or None
        self.kind, self.targets = kind, targets
        self.axes = list(kind.axes)
        self.load_cells = {a: LoadCell(loading.moving_dofs[a], specimen.force_factor(a)) for a in self.axes}
        from vlab.measure import kinds as provided  # what the kind declares (not at import: kinds -> fits -> Curve)

        self.extensometers, self.width, thickness = provided.gauges(kind, space, specimen)
        self.thickness = ThicknessGauge(space, material, specimen.thickness) if thickness is None else thickness
        self.readers = provided.extra_readers(kind, space, specimen, loading, material)
        self.curve = Curve(area0=kind.areas(specimen), kind=kind.name, extra={k: [] for k in self.readers})
        for a in self.axes:
            self.curve.stretch[a], self.curve.force[a], self.curve.strain[a] = [], [], []

    def __call__(self, level: Level) -> None:
        u, f_int = level.evaluation.u, level.evaluation.f_int
        c = self.curve
        c.t.append(level.t)
        if level.time is not None:
            c.time.append(level.time)
        control = self.kind.at(self.targets, level.t)
        for a in self.axes:
            c.stretch[a].append(control[a])
            c.force[a].append(self.load_cells[a].read(f_int))
            c.strain[a].append(self.extensometers[a].strain(u))
        if self.centre is not None:
            for key, value in self.centre.read(level.evaluation.F).items():
                c.centre.setdefault(key, []).append(value)
        for key, read in self.readers.items():
            c.extra[key].append(read(level))
        c.transverse_strain.append(self.width.strain(u))
        c.thickness_strain.append(self.thickness.strain(u))
