"""What renders and VTU files need from a run, as plain arrays that cross process boundaries.

A Snapshot holds the reference mesh, the displacement of its vertices and the per-cell fields at
the unloaded state and at every recorded level, and the current positions of the gauge marks.
The renders use the vertex values (vertices are the first scalar DOFs: straight-sided cells);
the VTU files get every node of the space (``vtk``: an order-2 space as quadratic VTK cells with
their mid-nodes, vlab.post.vtk_cells), the displacement of every node, and per cell the Cauchy
stress and Green–Lagrange strain tensors (``tensors``). A 2D sheet is stored in 3D with z = 0 (its
displacement has no z component) and without the thickness marks, which sit over the same point.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import skfem

from vlab.geometry.fixtures import Fixture, box
from vlab.geometry.symmetry import reflection
from vlab.post.fields import FIELDS, cell_fields
from vlab.post.vtk_cells import vtk_cells


@dataclass(frozen=True)
class Snapshot:
    """model: name; t: (n_frames,) load levels, frame 0 unloaded (t = 1 is the target); stretch:
    (n_frames,) grip stretch along x; displacement: (n_frames, n_vertices, 3) mm; fields: name ->
    (n_frames, n_cells); marks: name -> (reference (2, 3), current (n_frames, 2, 3)) mm.
    For the VTU files: vtk = (points (n_nodes, 3) mm, meshio cell type, connectivity);
    nodal_displacement (n_frames, n_nodes, 3) mm; tensors: name -> (n_frames, n_cells, 3, 3)
    ("cauchy" MPa, "green_lagrange" 1); time: (n_frames,) s, or None (quasi-static);
    grip_stretch: (n_frames, n_axes); control: what ``stretch`` holds (the kind's control_name);
    completed: whether the test reached its end; rest: the control at rest; view: (direction, up)
    of the specimen's photograph (vlab.geometry.specimen.View) or None (the default view);
    plates: per rigid plate (lo (3,), hi (3,), displacement (n_frames, 3)) mm; fixtures: the test
    kind's rigid fixtures (vlab.geometry.fixtures.Fixture: a die and its platens)."""

    model: str
    mesh: skfem.Mesh
    t: np.ndarray
    stretch: np.ndarray
    displacement: np.ndarray
    fields: dict[str, np.ndarray]
    marks: dict[str, tuple[np.ndarray, np.ndarray]]
    vtk: tuple[np.ndarray, str, np.ndarray] | None = None
    nodal_displacement: np.ndarray | None = None
    tensors: dict[str, np.ndarray] = field(default_factory=dict)
    time: np.ndarray | None = None
    grip_stretch: np.ndarray | None = None
    control: str = "grip stretch"  # what ``stretch`` holds: the test kind's control ("shear": the amount γ)
    completed: bool = True  # the test reached its end (False: stopped; the last frame is the last converged)
    rest: float = 1.0  # ``stretch`` at rest: 1 for a stretch, 0 for a shear γ or a twist
    view: tuple[np.ndarray, np.ndarray] | None = None
    plates: tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...] = ()
    fixtures: tuple[Fixture, ...] = ()

    @property
    def n_frames(self) -> int:
        return len(self.t)

    @property
    def points(self) -> np.ndarray:
        """(n_vertices, 3) reference vertex positions, mm (z = 0 for a sheet)."""
        p = self.mesh.p.T
        return np.hstack([p, np.zeros((len(p), 3 - p.shape[1]))])

    def rigid_parts(self) -> tuple[Fixture, ...]:
        """Every rigid part to draw: the plates (as boxes) and the kind's fixtures."""
        plates = tuple(Fixture("plate", *box(lo, hi), moved) for lo, hi, moved in self.plates)
        return plates + self.fixtures

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
    """Snapshot of a RunResult (its body is ``result.solver.body``)."""
    body, space, mesh = result.solver.body, result.space, result.specimen.mesh
    states = [body.evaluate(np.zeros(space.n_dofs))] + [lv.evaluation for lv in result.history.levels]
    n_vertices = mesh.nvertices
    d = space.dim
    u = np.stack([_in_3d(ev.u.reshape(-1, d)[:n_vertices]) for ev in states])
    per_state = [cell_fields(body, ev) for ev in states]
    fields = {name: np.stack([cf.get(name) for cf in per_state]) for name in FIELDS}
    if body.history is not None:  # history variables per cell (a scene with a history effect)
        per_state_history = [body.history.cell_history(ev) for ev in states]
        for name in per_state_history[0]:
            fields[name] = np.stack([h[name] for h in per_state_history])
    marks = {}
    for name, gauge in _gauge_marks(result.specimen).items():
        # on a symmetry-reduced model a mark behind a cut plane is drawn at its image on the part
        X = np.array([reflection(p, result.specimen.symmetry)[0] for p in (gauge.a, gauge.b)])
        probe = space.probe_matrix(X.T)
        marks[name] = (_in_3d(X), np.stack([_in_3d(X + probe @ ev.u.reshape(-1, d)) for ev in states]))
    t = np.array([0.0] + [lv.t for lv in result.history.levels])
    from vlab.loading.kinds import kind_of

    kind = kind_of(result.scene.test)
    targets = result.scene.test.targets
    grip = np.array([kind.at(targets, x) for x in t])  # every loaded axis' control per frame
    stretch = grip[:, 0]
    times = [lv.time for lv in result.history.levels]
    time = None if any(x is None for x in times) else np.array([0.0] + times)
    tensors = {name: np.stack([np.moveaxis(getattr(cf, name), -1, 0) for cf in per_state])
               for name in ("cauchy", "green_lagrange")}
    nodal = np.stack([_in_3d(ev.u.reshape(-1, d)) for ev in states])
    view = result.specimen.view
    control = kind.control_label(result.scene.test, result.scene.specimen.shape)
    return Snapshot(result.scene.material.model, mesh, t, stretch, u, fields, marks, vtk_cells(space),
                    nodal, tensors, time, grip, control, result.converged, kind.rest,
                    None if view is None else (np.asarray(view.direction, float), np.asarray(view.up, float)),
                    _plates(result.specimen, u), tuple(part.placed(_in_3d(mesh.p.T), u)
                                                        for part in kind.fixtures(result.specimen)))


def _plates(specimen, u: np.ndarray) -> tuple:
    """(lo, hi, displacement per frame) of each rigid plate of the specimen's view: the plate moves
    by the mean displacement of the vertices on its box's surface (it is rigid and bonded there)."""
    if specimen.view is None:
        return ()
    X = _in_3d(specimen.mesh.p.T)
    tol = 1e-9 * specimen.length_scale
    found = []
    for plate in specimen.view.plates:
        lo, hi = np.asarray(plate.lo, float), np.asarray(plate.hi, float)
        on = np.all((X >= lo - tol) & (X <= hi + tol), axis=1)
        if not on.any():
            raise ValueError(f"plate {plate} touches no vertex of the {specimen.shape} mesh")
        found.append((lo, hi, u[:, on].mean(axis=1)))
    return tuple(found)
