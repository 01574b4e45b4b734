"""What renders and VTU files need from a run, as plain arrays that cross process boundaries.

A Snapshot holds the reference mesh, the displacement of its vertices and the per-cell fields at
the unloaded state and at every recorded level, and the current positions of the gauge marks.
For order-2 spaces only the vertex values are kept (vertices are the first scalar DOFs), so the
pictures show the straight-sided cells of the mesh. A 2D sheet is stored in 3D with z = 0 (its
displacement has no z component) and without the thickness marks, which sit over the same point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import skfem

from vlab.geometry.symmetry import reflection
from vlab.post.fields import FIELDS, cell_fields


@dataclass(frozen=True)
class Snapshot:
    """model: name; t: (n_frames,) load levels, frame 0 unloaded (t = 1 is the target); stretch:
    (n_frames,) grip stretch along x; displacement: (n_frames, n_vertices, 3) mm; fields: name ->
    (n_frames, n_cells); marks: name -> (reference (2, 3), current (n_frames, 2, 3)) mm;
    completed: whether the test reached its end."""

    model: str
    mesh: skfem.Mesh
    t: np.ndarray
    stretch: np.ndarray
    displacement: np.ndarray
    fields: dict[str, np.ndarray]
    marks: dict[str, tuple[np.ndarray, np.ndarray]]
    completed: bool = True  # the test reached its end (False: stopped; the last frame is the last converged)

    @property
    def n_frames(self) -> int:
        return len(self.t)

    @property
    def points(self) -> np.ndarray:
        """(n_vertices, 3) reference vertex positions, mm (z = 0 for a sheet)."""
        p = self.mesh.p.T
        return np.hstack([p, np.zeros((len(p), 3 - p.shape[1]))])

    def field_range(self, name: str, frame: int = -1) -> tuple[float, float]:
        values = self.fields[name][frame]
        return float(values.min()), float(values.max())


def _gauge_marks(specimen) -> dict:
    marks = {f"extensometer {'xy'[axis]}": m for axis, m in specimen.extensometers.items()}
    marks["transverse"] = specimen.transverse[0]
    if specimen.sheet_thickness is None:
        marks["thickness"] = specimen.thickness
    return marks


def _in_3d(x: np.ndarray) -> np.ndarray:
    """(..., dim) -> (..., 3), padding with zeros."""
    return np.concatenate([x, np.zeros(x.shape[:-1] + (3 - x.shape[-1],))], axis=-1)


def take_snapshot(result) -> Snapshot:
    """Snapshot of a RunResult (its body is ``result.extra['body']``)."""
    body, space, mesh = result.extra["body"], result.space, result.specimen.mesh
    states = [body.evaluate(np.zeros(space.n_dofs))] + [lv.evaluation for lv in result.history.levels]
    n_vertices = mesh.nvertices
    d = space.dim
    u = np.stack([_in_3d(ev.u.reshape(-1, d)[:n_vertices]) for ev in states])
    per_state = [cell_fields(body, ev) for ev in states]
    fields = {name: np.stack([cf.get(name) for cf in per_state]) for name in FIELDS}
    if hasattr(body, "cell_history"):  # history variables per cell (a scene with a history effect)
        per_state_history = [body.cell_history(ev) for ev in states]
        for name in per_state_history[0]:
            fields[name] = np.stack([h[name] for h in per_state_history])
    marks = {}
    for name, gauge in _gauge_marks(result.specimen).items():
        # on a symmetry-reduced model a mark behind a cut plane is drawn at its image on the part
        X = np.array([reflection(p, result.specimen.symmetry)[0] for p in (gauge.a, gauge.b)])
        probe = space.probe_matrix(X.T)
        marks[name] = (_in_3d(X), np.stack([_in_3d(X + probe @ ev.u.reshape(-1, d)) for ev in states]))
    t = np.array([0.0] + [lv.t for lv in result.history.levels])
    stretch = 1.0 + t * (result.scene.test.stretch[0] - 1.0)
    return Snapshot(result.scene.material.model, mesh, t, stretch, u, fields, marks, result.converged)
