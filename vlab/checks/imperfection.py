"""A small geometric imperfection in the buckling mode, so a test follows the post-buckled path.

A perfect specimen stays on its fundamental (straight) path until K_ff loses positive
definiteness, where the path bifurcates; a displacement-controlled solver cannot choose a branch
and the monitor stops the test there. Moving the reference nodes by
    X ← X + a · φ / max_nodes |φ_lateral|
(φ the mode of the first critical state, a the amplitude in mm = imperfection × thickness) turns
the bifurcation into a smooth path: the lateral deflection grows from the start and the force
levels off below the perfect specimen's critical load (Southwell's imperfect column).

The perturbation keeps the grip faces where they are (φ vanishes on the clamped DOFs).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import skfem

from vlab.geometry.specimen import GaugeMarks, Specimen


def imperfect_specimen(specimen: Specimen, space, mode: np.ndarray, amplitude: float,
                       axis: int = 0) -> Specimen:
    """The specimen with its mesh vertices moved by the mode scaled to a lateral peak ``amplitude``
    (mm). ``space`` is the (perfect) specimen's displacement space (vertices first), ``mode`` a
    full DOF vector on it. Gauge marks are material points: they move with the vertex shifts
    interpolated by the mesh's own (linear) map, so a mark on the surface stays on the moved
    surface (the order-2 interpolation of the mode could leave it just outside the facets)."""
    nodes = mode.reshape(-1, 3)
    lateral = [c for c in range(3) if c != axis]
    peak = float(np.max(np.linalg.norm(nodes[:, lateral], axis=1), initial=0.0))
    if peak == 0.0:
        raise ValueError("the buckling mode has no lateral displacement to seed an imperfection")
    mesh = specimen.mesh
    n = mesh.p.shape[1]
    if not np.allclose(space.node_coordinates[:n], mesh.p.T):
        raise ValueError("the space's first nodes are not the mesh vertices; cannot seed the mode")
    shift = (amplitude / peak) * nodes[:n]
    linear = skfem.Basis(mesh, skfem.ElementHex1() if isinstance(mesh, skfem.MeshHex) else skfem.ElementTetP1())

    def moved(marks: GaugeMarks) -> GaugeMarks:
        points = np.array([marks.a, marks.b], dtype=float)
        points = points + linear.probes(points.T).tocsr() @ shift
        return GaugeMarks(tuple(points[0]), tuple(points[1]))

    return dataclasses.replace(
        specimen, mesh=type(mesh)(mesh.p + shift.T, mesh.t),
        extensometers={a: moved(m) for a, m in specimen.extensometers.items()},
        transverse={a: moved(m) for a, m in specimen.transverse.items()},
        thickness=moved(specimen.thickness))
