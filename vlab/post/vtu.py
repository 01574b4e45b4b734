"""Deformed meshes for ParaView: one VTU file per frame plus a PVD time series.

Each VTU holds the reference mesh of the FE space (an order-2 space as quadratic cells with their
mid-nodes: tetra10, hexahedron27, triangle6, quad9; :mod:`vlab.post.vtk_cells`), the point field
``displacement`` (mm, every node; ParaView's "Warp By Vector" shows the deformed shape), the cell
fields of :mod:`vlab.post.fields` and the history variables, the cell tensors ``cauchy`` (σ, MPa)
and ``green_lagrange`` (E, 1) as 9-component (3 × 3, row-major) arrays, and as field data the
frame's ``grip_stretch`` (one value per test axis), ``load_level`` t and ``time`` (s, if any).

The PVD's timesteps must increase strictly: ParaView keeps one dataset per time value, so the
load level t, which returns to 0 in a load–unload or cyclic test (0 → 1 → 0), would hide the
unloading. The timestep is the test's physical time where it has one (and it increases
strictly), else the frame index 0, 1, 2, …; the grip stretch stays readable as field data.
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
import pyvista as pv
import skfem.io.meshio

from vlab.post.snapshot import Snapshot


def reference_grid(mesh) -> pv.UnstructuredGrid:
    """The scikit-fem mesh (vertices only) as a pyvista grid in VTK node order (for renders)."""
    return pv.from_meshio(skfem.io.meshio.to_meshio(mesh))


def space_grid(snapshot: Snapshot) -> pv.UnstructuredGrid:
    """The FE space's nodes and cells (quadratic for order 2) as a pyvista grid."""
    if snapshot.vtk is None:
        return reference_grid(snapshot.mesh)
    points, cell, connectivity = snapshot.vtk
    return pv.from_meshio(meshio.Mesh(points, [(cell, connectivity)]))


def frame_grid(snapshot: Snapshot, frame: int, base: pv.UnstructuredGrid | None = None) -> pv.UnstructuredGrid:
    """The space's grid carrying frame ``frame``'s displacement, cell fields, tensors, field data."""
    grid = (base if base is not None else space_grid(snapshot)).copy()
    nodal = snapshot.nodal_displacement if snapshot.vtk is not None else None
    grid.point_data["displacement"] = (nodal if nodal is not None else snapshot.displacement)[frame]
    for name, values in snapshot.fields.items():
        grid.cell_data[name] = values[frame]
    for name, values in snapshot.tensors.items():
        grid.cell_data[name] = values[frame].reshape(len(values[frame]), 9)
    stretch = snapshot.grip_stretch[frame] if snapshot.grip_stretch is not None else [snapshot.stretch[frame]]
    grid.field_data["grip_stretch"] = np.asarray(stretch, float)
    grid.field_data["load_level"] = np.array([snapshot.t[frame]], float)
    if snapshot.time is not None:
        grid.field_data["time"] = np.array([snapshot.time[frame]], float)
    return grid


def timesteps(snapshot: Snapshot) -> np.ndarray:
    """Strictly increasing PVD time values: the physical time if it increases strictly, else 0, 1, …"""
    time = snapshot.time
    if time is not None and np.all(np.diff(time) > 0.0):
        return np.asarray(time, float)
    return np.arange(snapshot.n_frames, dtype=float)


def write_time_series(snapshot: Snapshot, folder: Path, stem: str) -> Path:
    """``folder/<stem>_NNN.vtu`` per frame and ``folder/<stem>.pvd`` listing them; returns the PVD."""
    folder = Path(folder)
    (folder / "vtu").mkdir(parents=True, exist_ok=True)
    base = space_grid(snapshot)
    entries = []
    for frame, step in enumerate(timesteps(snapshot)):
        name = f"vtu/{stem}_{frame:03d}.vtu"
        frame_grid(snapshot, frame, base).save(folder / name)
        entries.append(f'    <DataSet timestep="{step:.17g}" part="0" file={quoteattr(name)}/>')
    pvd = folder / f"{stem}.pvd"
    pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                   + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return pvd
