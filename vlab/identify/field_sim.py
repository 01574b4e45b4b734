"""One whole vlab test for a field fit: the load cell and the camera face's displacement at every
recorded level, with their exact sensitivities to the fitted constants.

The run's observer is vlab.identify.fe_levels.LevelSensitivities (K_ff du_f/dp_j = −∂f_int,f/∂p_j
with the step's own factor) keeping, besides the load cell's dF/dp, the in-plane displacement of
the face's vertices u (n_face, 2) mm and du/dp (n_p, n_face, 2). The control is the grip
displacement Δ_k = (λ_k − 1) L_grip (mm, the crosshead travel, L_grip the grip separation).
At the data's displacements Δ_i everything is the cubic spline through (0, 0) and the levels (the
displacement is prescribed, so it does not move with p): exact at a recorded level.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from vlab.fields import SceneError
from vlab.identify.fe_levels import LevelSensitivities

__all__ = ["FieldSimulation", "simulate_field"]

REACH = 1e-6  # the data's last displacement may pass the test's by this share (round-off of a written CSV)


@dataclass(frozen=True)
class FieldSimulation:
    """displacement (k,) mm; force (k,) N; dforce (k, n_p); u (k, n_face, 2) mm; du (k, n_p, n_face, 2);
    face: the camera's face (vlab.dic.face.Face); warnings of the run; dofs; counts."""

    displacement: np.ndarray
    force: np.ndarray
    dforce: np.ndarray
    u: np.ndarray
    du: np.ndarray
    face: object
    warnings: tuple
    dofs: int
    counts: dict

    def at(self, d: np.ndarray, name: str):
        """(u, du, F, dF) at the grip displacements d: splines in Δ through (0, 0) and the levels."""
        top = float(self.displacement[-1])
        if np.max(d) > top * (1 + REACH):
            raise SceneError(f"{name}: levels.csv reaches a grip displacement of {np.max(d):.6g} mm, beyond the "
                             f"scene's test ({top:.6g} mm): raise the scene's test.stretch")
        D = np.r_[0.0, self.displacement]
        d = np.minimum(d, top)

        def spline(a):
            return CubicSpline(D, np.concatenate([np.zeros((1,) + a.shape[1:]), a]), axis=0)(d)
        return spline(self.u), spline(self.du), spline(self.force), spline(self.dforce)


class _FieldObserver(LevelSensitivities):
    """LevelSensitivities of the x load cell (its reading channel 0) that also keeps the face's u
    and du/dp per level."""

    def __init__(self, prepared, tangents, fe: dict, values: dict, face, channels):
        super().__init__(prepared, tangents, fe, values, channels)
        self.face, self.u, self.du = face, [], []
        self._du = None

    def keep(self, j: int, du: np.ndarray) -> None:
        self._du[j] = self.face.in_plane(du.reshape(-1, 3))

    def __call__(self, level) -> None:
        self._du = np.zeros((len(self.fe["parameters"]), len(self.face.nodes), 2))
        super().__call__(level)
        self.u.append(self.face.in_plane(level.evaluation.u.reshape(-1, 3)))
        self.du.append(self._du)


def simulate_field(fe: dict, values: dict, face_side: tuple[int, int]) -> FieldSimulation:
    """Run fe's scene at ``values``; RuntimeError if the test fails, SceneError if the face is not there."""
    from vlab.dic.face import FaceError, face_of
    from vlab.identify.fe_readings import quantities
    from vlab.identify.fe_sensitivity import run_quietly, scene_with

    made: list[_FieldObserver] = []
    scene = scene_with(fe, values)
    channels = quantities(fe, scene)  # the extensometer and the x load cell (fe_spec._channels)

    def observe(prepared, tangents):
        try:
            face = face_of(prepared.specimen.mesh, *face_side)
        except FaceError as exc:
            raise SceneError(f"data.camera.face: {exc}") from None
        made.append(_FieldObserver(prepared, tangents, fe, values, face, channels))
        return made[-1]

    result = run_quietly(fe, scene, values, observe)
    obs, curve = made[0], result.curve
    if len(curve.force[0]) != len(obs.rows):
        raise SceneError("fe.scene: the recorded levels and the solver's levels differ")
    grip = (np.array(curve.stretch[0]) - 1.0) * float(result.specimen.grip_separation[0])
    counts = {"factorizations": int(result.history.factorizations),
              "sensitivity_factorizations": obs.factorizations, "sensitivity_solves": obs.solves,
              "levels": len(obs.rows)}
    return FieldSimulation(grip, np.array(curve.force[0]), np.array([r[0][0] for r in obs.rows]),
                           np.array(obs.u), np.array(obs.du), obs.face, tuple(result.diagnostics.warnings),
                           int(result.space.n_dofs), counts)
