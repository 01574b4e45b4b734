"""What a run produces: the serialisable result and, apart from it, the live solver objects.

:class:`Diagnostics` holds everything results.json reports besides the curve and the elastic
constants, as plain data (dicts, lists, numbers, strings). :class:`SolverObjects` holds the live
objects of the finished solve (the body with its state, the DOF partition, the critical state
with its mode) for snapshots, renders and tests; results.json never reads them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from vlab.checks.buckling import CriticalState
    from vlab.fe.assembly import Partition
    from vlab.fe.body import Body
    from vlab.fe.space import DisplacementSpace
    from vlab.fe.stepping import SolveHistory
    from vlab.geometry.specimen import Specimen
    from vlab.measure.elastic_constants import ElasticConstants
    from vlab.measure.recorder import Curve
    from vlab.scene import Scene

__all__ = ["Diagnostics", "SolverObjects", "RunResult"]


@dataclass
class Diagnostics:
    """A run's findings beyond the curve, each the value of one results.json entry."""

    mesh_quality: dict  # mesh.quality: measure, min/mean quality, max aspect ratio, worst element
    linear_solver: dict  # solver.linear: requested, used for Newton, direct back end
    tangent_kernel: str  # solver.tangent_kernel: "numpy" or "compiled (numba x, n threads)"
    warnings: list[str] = field(default_factory=list)
    crosshead: dict | None = None  # measured.E_crosshead(_fit): modulus from grip separation, MPa
    uncertainty: dict | None = None  # measured.uncertainty (effects.noise)
    cruciform: dict | None = None  # centre stress, correction factors
    homogeneity: dict | None = None  # gauge-section spread at small strain and at the end
    bending: dict | None = None  # ASTM E1012 percent bending of a misaligned test (measure/bending.py)
    stability: list[dict] = field(default_factory=list)  # inertia per level
    lateral_deflection: list[float] = field(default_factory=list)  # mm, per level
    critical: dict | None = None  # first loss of stability, its classification
    imperfection: dict | None = None  # a seeded buckling mode: {"perfect_critical": the perfect pass's}
    effects: dict | None = None  # declared effects, protocol, history maxima per level
    accuracy_estimate: dict | None = None  # vlab.study.estimate (set by the CLI), None if off


@dataclass
class SolverObjects:
    """Live objects of the finished solve (never serialised)."""

    body: "Body"
    partition: "Partition"
    critical_state: "CriticalState | None" = None  # with its mode (full DOF vector)


@dataclass
class RunResult:
    scene: "Scene"
    specimen: "Specimen"
    space: "DisplacementSpace"
    curve: "Curve"
    constants: "ElasticConstants"
    history: "SolveHistory"
    timing: dict[str, float]
    diagnostics: Diagnostics
    solver: SolverObjects
    reference: dict | None = None
    dic: object | None = None  # vlab.pipeline.dic.DicRun of a scene with [instruments.dic]

    @property
    def converged(self) -> bool:
        return self.history.failure is None

    @property
    def body(self) -> "Body":
        return self.solver.body

    @property
    def final_displacement(self) -> np.ndarray:
        levels = self.history.levels
        return levels[-1].state.u if levels else np.zeros(self.space.n_dofs)
