"""Sensitivities of a test's readings at every recorded level, with the factor the step already has.

An observer of the run (vlab.run.run_scene(observe=...)): called with each converged level after
the stability monitor vetted that state, when the monitor's TangentCache holds K at the state,
assembled and K_ff factorized (the stepper reuses that factor for the next predictor and the first
Newton correction). At r(u, p) = f_int(u; p) − f_reaction = 0 on the free DOFs, for each constant p_j
    K_ff du_f/dp_j = −g_f,      g = ∂f_int/∂p_j = Σ_e ∫ ∂P/∂p_j : ∇N dV      (N per unit of p_j)
(∂P/∂p from vlab.identify.fe_stress, assembled like the internal force; du/dp = 0 on the grips):
one back-substitution per constant with that factor, no assembly and no factorization of its own.
The readings, per loading axis a (one for uniaxial, two for a cruciform):
    load cell    dF_a/dp = c_a Σ_{grip a} (g + K_{grip,f} du_f/dp)            (c_a the symmetry factor)
    extensometer de_a/dp = n_a · (δx_b − δx_a) / L0, δx = the marks' displacement along du/dp,
                 n_a the unit vector between the marks (the reading |x_b − x_a|/L0 − 1 is smooth).
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
    """Observer: rows (dF (n_axes, n_p), de (n_axes, n_p)) per recorded level."""

    def __init__(self, prepared, tangents, fe: dict, values: dict, axes: tuple[int, ...],
                 refactorize: bool = False):
        from vlab.measure.instruments import extensometers

        space, specimen = prepared.space, prepared.specimen
        if space.dim != 3:
            raise SceneError("fe.scene: FE-in-the-loop fits need a 3-D specimen (not a plane sheet)")
        self.space, self.tangents, self.fe, self.values = space, tangents, fe, values
        self.refactorize = refactorize  # the previous way, kept for the A/B count: K and K_ff anew
        self.body, self.partition = prepared.body, prepared.partition
        self.free = prepared.partition.free
        self.grips = [np.asarray(prepared.loading.moving_dofs[a]) for a in axes]
        position = np.full(space.n_dofs, -1)  # a prescribed DOF's column in K_fp
        position[self.partition.prescribed] = np.arange(len(self.partition.prescribed))
        self.grip_positions = [position[g] for g in self.grips]
        self.factors = [specimen.force_factor(a) for a in axes]
        self.ext = extensometers(space, [specimen.extensometers[a] for a in axes], specimen.symmetry)
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
        K_grips = self._grip_rows(tangent)
        directions = [_direction(e, ev.u) for e in self.ext]
        dF = np.zeros((len(self.grips), len(names)))
        de = np.zeros_like(dF)
        for j, p in enumerate(names):
            g = scatter_vector(self.space, element_forces(self.space, dP[p]))
            du_f = -tangent.factor.solve(g[self.free])
            self.solves += 1
            du = np.zeros(self.space.n_dofs)
            du[self.free] = du_f
            self.keep(j, du)
            for a, (grip, c, Kg, ext, n) in enumerate(zip(self.grips, self.factors, K_grips, self.ext, directions)):
                dF[a, j] = c * float(g[grip].sum() + (Kg @ du_f).sum())
                dx = _marks_displacement(ext, du)
                de[a, j] = float(n @ (dx[1] - dx[0])) / ext.length0
        self.rows.append((dF, de))

    def keep(self, j: int, du: np.ndarray) -> None:
        """Hook: du/dp_j (all DOFs) of the level being differentiated, for a subclass that needs
        the displacement field's sensitivity (vlab.identify.field_sim)."""

    def _grip_rows(self, tangent) -> list:
        """K[g, free] for each grip's (prescribed) DOFs g: rows of K_fpᵀ, K being symmetric."""
        rows = tangent.Kfp.T.tocsr()
        return [rows[g] for g in self.grip_positions]

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


def _direction(ext, u: np.ndarray) -> np.ndarray:
    """Unit vector from mark a to mark b in the deformed state (mirror images reflected back)."""
    from vlab.geometry.symmetry import reflect_back

    x = ext._X + ext._probe @ u.reshape(-1, ext._dim)
    n = reflect_back(x[1], ext._signs[1], ext._planes) - reflect_back(x[0], ext._signs[0], ext._planes)
    return n / np.linalg.norm(n)


def _marks_displacement(ext, du: np.ndarray) -> np.ndarray:
    """δx of both marks along du (the probe is linear; reflections only flip components)."""
    from vlab.geometry.symmetry import reflect_back

    d = ext._probe @ du.reshape(-1, ext._dim)
    zero = np.zeros(ext._dim)
    return np.array([reflect_back(ext._X[i] + d[i], ext._signs[i], ext._planes)
                     - reflect_back(ext._X[i] + zero, ext._signs[i], ext._planes) for i in (0, 1)])
