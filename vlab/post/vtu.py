"""Deformed meshes for ParaView: one VTU file per frame plus a PVD time series.

Each VTU holds the reference mesh (cell connectivity converted to VTK's node order by scikit-fem's
meshio adapter), the point field ``displacement`` (mm; use ParaView's "Warp By Vector" to see the
deformed shape) and the cell fields of :mod:`vlab.post.fields`. The PVD's timestep is the load
level t (0 unloaded, 1 at the target grip stretch).
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import pyvista as pv
import skfem.io.meshio

from vlab.post.snapshot import Snapshot


def reference_grid(mesh) -> pv.UnstructuredGrid:
    """The scikit-fem mesh (vertices only) as a pyvista grid in VTK node order."""
    return pv.from_meshio(skfem.io.meshio.to_meshio(mesh))


def frame_grid(snapshot: Snapshot, frame: int, base: pv.UnstructuredGrid | None = None) -> pv.UnstructuredGrid:
    """Reference grid carrying frame ``frame``'s displacement and cell fields."""
    grid = (base if base is not None else reference_grid(snapshot.mesh)).copy()
    grid.point_data["displacement"] = snapshot.displacement[frame]
    for name, values in snapshot.fields.items():
        grid.cell_data[name] = values[frame]
    return grid


def write_time_series(snapshot: Snapshot, folder: Path, stem: str) -> Path:
    """``folder/<stem>_NNN.vtu`` per frame and ``folder/<stem>.pvd`` listing them; returns the PVD."""
    folder = Path(folder)
    (folder / "vtu").mkdir(parents=True, exist_ok=True)
    base = reference_grid(snapshot.mesh)
    entries = []
    for frame in range(snapshot.n_frames):
        name = f"vtu/{stem}_{frame:03d}.vtu"
        frame_grid(snapshot, frame, base).save(folder / name)
        entries.append(f'    <DataSet timestep="{snapshot.t[frame]:.10g}" part="0" file={quoteattr(name)}/>')
    pvd = folder / f"{stem}.pvd"
    pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                   + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return pvd
