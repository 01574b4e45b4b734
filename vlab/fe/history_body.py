"""A body whose material remembers: internal variables at every quadrature point.

Same interface as HyperelasticBody (``evaluate(u) -> Evaluation``, ``stiffness(evaluation)``), so
Newton, its energy line search and the load stepping are unchanged. The material is a
vlab.materials.history.HistoryMaterial; within one increment of ``dt`` seconds its converged
state at the start of the increment is frozen and the body's energy is the incremental potential

    W_inc(u) = Σ_e Σ_q ψ_inc(F(u); state_n, dt) dx,

whose gradient is the internal force with the algorithmic stress and whose Hessian is the
stiffness with the algorithmic tangent. The stepper calls ``begin_increment(dt)`` before each
substep and ``commit(evaluation)`` only after the substep converged and was accepted: a rejected
(cut-back) substep leaves ``state`` untouched, since ``evaluate`` and ``stiffness`` only read it.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from vlab.fe.assembly import SparsityPattern, element_forces, element_stiffness, scatter_vector
from vlab.fe.problem import J_COLLAPSE, Evaluation
from vlab.fe.body import BodyDefaults
from vlab.fe.space import DisplacementSpace
from vlab.materials.history import HistoryMaterial
from vlab.fe.cell_fields import cauchy, cell_average
from vlab.tensor import det


class HistoryBody(BodyDefaults):
    """Couples a HistoryMaterial to a displacement space; owns the quadrature-point state."""


    @property
    def history(self) -> "HistoryBody":
        """The history capability (vlab.fe.body.HistoryCapability) is this body's own."""
        return self

    def __init__(self, space: DisplacementSpace, material: HistoryMaterial):
        self.space = space
        self.material = material
        self.pattern = SparsityPattern.build(space.element_nodes)
        self.state = material.initial_state(space.dx.shape)
        self.dt = 0.0
        self._last: tuple[int, dict[str, np.ndarray]] | None = None  # the last commit's cell fields
        self._kept: dict[int, dict[str, np.ndarray]] = {}  # id(recorded evaluation) -> cell fields

    def begin_increment(self, dt: float) -> None:
        """The time step (s) of the next substep; the state stays that of the last commit."""
        self.dt = float(dt)

    def evaluate(self, u: np.ndarray) -> Evaluation:
        F = self.space.deformation_gradient(u)
        J = det(F)
        worst = np.unravel_index(int(np.argmin(J)), J.shape)
        where = (int(worst[0]), int(worst[1]))
        min_J = float(J[worst])
        if not min_J > J_COLLAPSE:
            return Evaluation(u, F, np.inf, None, min_J, where)
        response = self.material.respond(F, self.state, self.dt, with_tangent=False)
        W = float(np.sum(response.energy * self.space.dx))
        if not np.isfinite(W):
            return Evaluation(u, F, np.inf, None, min_J, where)
        f_int = scatter_vector(self.space, element_forces(self.space, response.stress))
        return Evaluation(u, F, W, f_int, min_J, where)

    def stiffness(self, evaluation: Evaluation) -> sp.csr_matrix:
        """K = ∂f_int/∂u with the algorithmic tangent of the current increment, N/mm."""
        A = self.material.respond(evaluation.F, self.state, self.dt, with_tangent=True).tangent
        return self.pattern.matrix(element_stiffness(self.space, A))

    def commit(self, evaluation: Evaluation) -> None:
        """Advance the state to the converged end of the increment (called once per accepted substep)."""
        P = self.material.respond(evaluation.F, self.state, self.dt, with_tangent=False).stress
        self.state = self.material.update(evaluation.F, self.state, self.dt)
        fields = {"cauchy": cell_average(cauchy(P, evaluation.F), self.space.dx)}
        if self.material.history_fields is not None:
            for name, values in self.material.history_fields(self.state, evaluation.F).items():
                fields[name] = cell_average(values, self.space.dx)
        self._last = (id(evaluation), fields)

    def keep_cells(self, evaluation: Evaluation) -> None:
        """Keep the cell fields of a recorded level (the last commit) for the VTU output."""
        if self._last is not None and self._last[0] == id(evaluation):
            self._kept[id(evaluation)] = self._last[1]

    def cell_fields_of(self, evaluation: Evaluation) -> dict[str, np.ndarray] | None:
        return self._kept.get(id(evaluation))

    def cell_cauchy(self, evaluation: Evaluation) -> np.ndarray:
        """Cell-averaged Cauchy stress of a recorded level (3,3,e); the virgin state otherwise."""
        kept = self.cell_fields_of(evaluation)
        if kept is not None:
            return kept["cauchy"]
        fresh = self.material.initial_state(self.space.dx.shape)
        P = self.material.respond(evaluation.F, fresh, 0.0, with_tangent=False).stress
        return cell_average(cauchy(P, evaluation.F), self.space.dx)

    def cell_history(self, evaluation: Evaluation) -> dict[str, np.ndarray]:
        """History fields per cell of a recorded level (zeros for the unloaded state)."""
        kept = self.cell_fields_of(evaluation) or {}
        names = (self.material.history_fields(self.material.initial_state((1, 1)))
                 if self.material.history_fields is not None else {})
        n = self.space.dx.shape[0]
        return {name: kept.get(name, np.zeros(n)) for name in names}
