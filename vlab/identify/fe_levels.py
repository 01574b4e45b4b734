"""Sensitivities of a test's readings at every recorded level, with the factor the step already has.

An observer of the run (vlab.run.run_scene(observe=...)): called with each converged level after
the stability monitor vetted that state, when the monitor's TangentCache holds K at the state,
assembled and K_ff factorized (the stepper reuses that factor for the next predictor and the first
Newton correction). At r(u, p) = f_int(u; p) − f_reaction = 0 on the free DOFs, for each constant p_j
    K_ff du_f/dp_j = −g_f,      g = ∂f_int/∂p_j = Σ_e ∫ ∂P/∂p_j : ∇N dV      (N per unit of p_j)
(∂P/∂p from vlab.identify.fe_stress, assembled like the internal force; du/dp = 0 on the grips):
one back-substitution per constant with that factor, no assembly and no factorization of its own.
The reactions move by df/dp_j = g + K du/dp_j on the prescribed DOFs (g_p + K_fpᵀ du_f/dp_j) and
by 0 on the free ones; each channel's control and reading (vlab.identify.fe_readings) turn du/dp
and df/dp into their own derivatives by their probes (vlab.identify.fe_probes: the load cell
dF_a/dp = c_a Σ_{grip a} df/dp, the extensometer, the torque, the cavity's and the liquid's
pressure, ...).
``factorizations`` counts the factorizations this observer caused (0 when the monitor's factor is
there, as on every run with the monitor: measured in tests/test_fit_fe_levels.py), ``solves`` its
back-substitutions.
"""

from __future__ import annotations

import numpy as np

from vlab.fields import SceneError
from vlab.identify.fe_stress import stress_derivatives

__all__ = ["LevelSensitivities"]


class LevelSensitivities:
    """Observer: rows (d reading (n_channels, n_p), d control (n_channels, n_p)) per recorded level;
    ``channels`` the (control, reading) Quantity pairs of vlab.identify.fe_readings."""

    def __init__(self, prepared, tangents, fe: dict, values: dict, channels, refactorize: bool = False):
        space = prepared.space
        if space.dim != 3:
            raise SceneError("fe.scene: FE-in-the-loop fits need a 3-D specimen (not a plane sheet)")
        self.space, self.tangents, self.fe, self.values = space, tangents, fe, values
        self.refactorize = refactorize  # the previous way, kept for the A/B count: K and K_ff anew
        self.body, self.partition = prepared.body, prepared.partition
        self.free = prepared.partition.free
        self.probes = [(c.probe(prepared, c.axis), r.probe(prepared, r.axis)) for c, r in channels]
        self.rows: list[tuple[np.ndarray, np.ndarray]] = []
        self.factorizations = 0
        self.solves = 0
        self.reused = 0

    def __call__(self, level) -> None:
        from vlab.fe.assembly import element_forces, scatter_vector

        ev = level.evaluation
        tangent = self._tangent(ev)
        names = self.fe["parameters"]
        dP = stress_derivatives(ev.F, self.fe.get("model", "neo-hookean"), self.values, names,
                                self.fe.get("volumetric"))
        prescribed = self.partition.prescribed
        du = np.zeros((self.space.n_dofs, len(names)))
        df = np.zeros_like(du)
        for j, p in enumerate(names):
            g = scatter_vector(self.space, element_forces(self.space, dP[p]))
            du_f = -tangent.factor.solve(g[self.free])
            self.solves += 1
            du[self.free, j] = du_f
            df[prescribed, j] = g[prescribed] + tangent.Kfp.T @ du_f
            self.keep(j, du[:, j])
        dc = np.array([control(level, du, df) for control, _ in self.probes])
        dr = np.array([reading(level, du, df) for _, reading in self.probes])
        self.rows.append((dr, dc))

    def keep(self, j: int, du: np.ndarray) -> None:
        """Hook: du/dp_j (all DOFs) of the level being differentiated, for a subclass that needs
        the displacement field's sensitivity (vlab.identify.field_sim)."""

    def _tangent(self, ev):
        """The monitor's factor of this state (no work if it holds it), or, with
        ``refactorize``, K assembled and K_ff factorized here (counted)."""
        if self.refactorize:
            from vlab.fe.newton import Tangent
            from vlab.fe.linsolve import factorize

            Kff, Kfp = self.partition.blocks(self.body.stiffness(ev).tocsr())
            self.factorizations += 1
            return Tangent(factorize(Kff), Kfp)
        before = self.tangents.factorizations
        self.reused += self.tangents.holds(ev) is not None
        tangent = self.tangents.at(ev)
        self.factorizations += self.tangents.factorizations - before
        return tangent

