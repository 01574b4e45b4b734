"""Deformed meshes for ParaView: one VTU file per frame plus a PVD time series.

Each VTU holds the reference mesh (cell connectivity converted to VTK's node order by scikit-fem's
meshio adapter), the point field ``displacement`` (mm; use ParaView's "Warp By Vector" to see the
deformed shape) and the cell fields of :mod:`vlab.post.fields`. The PVD's timestep is the load
level t (0 unloaded, 1 at the target grip stretch).

The files are written here directly (VTK XML UnstructuredGrid, inline base64 "binary" arrays,
zlib-compressed, UInt64 headers, little endian), not through pyvista: importing pyvista and VTK cost a
run without renders ~0.3 s of its ~1 s overhead, and a grid copy per frame. pyvista is imported
only for the renders (``reference_grid``).
"""

from __future__ import annotations

import base64
import zlib
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
import skfem.io.meshio

from vlab.post.snapshot import Snapshot

ZLIB_LEVEL = 1  # block16.toml, 11 frames: 8.9 MB raw → 1.3 MB (as pyvista wrote); level 6 took 7× longer
VTK_TYPES = {"triangle": 5, "quad": 9, "tetra": 10, "hexahedron": 12, "wedge": 13}


def reference_grid(mesh):
    """The scikit-fem mesh (vertices only) as a pyvista grid in VTK node order (renders)."""
    import pyvista as pv

    return pv.from_meshio(skfem.io.meshio.to_meshio(mesh))


def _array(name: str, values: np.ndarray, vtk_type: str, components: int) -> str:
    """An inline zlib-compressed binary DataArray: one block, header (1, size, size, compressed
    size) as UInt64, header and data base64-encoded separately (VTK's layout for compressed data)."""
    raw = np.ascontiguousarray(values).tobytes()
    packed = zlib.compress(raw, ZLIB_LEVEL)
    header = np.array([1, len(raw), len(raw), len(packed)], dtype="<u8").tobytes()
    data = (base64.b64encode(header) + base64.b64encode(packed)).decode("ascii")
    return (f'<DataArray type="{vtk_type}" Name={quoteattr(name)} NumberOfComponents="{components}" '
            f'format="binary">{data}</DataArray>')


def _float_field(name: str, values: np.ndarray) -> str:
    values = np.asarray(values, dtype="<f8")
    components = 1 if values.ndim == 1 else values.shape[1]
    return _array(name, values, "Float64", components)


class _Topology:
    """Points (padded to 3D) and the cell arrays of a mesh, in VTK order, encoded once."""

    def __init__(self, mesh):
        m = skfem.io.meshio.to_meshio(mesh)
        points = np.zeros((len(m.points), 3))
        points[:, :m.points.shape[1]] = m.points
        (kind, cells), = m.cells_dict.items()
        self.n_points, self.n_cells = len(points), len(cells)
        self.xml = ("<Points>" + _array("Points", points.astype("<f8"), "Float64", 3) + "</Points><Cells>"
                    + _array("connectivity", cells.astype("<i8").ravel(), "Int64", 1)
                    + _array("offsets", (np.arange(1, len(cells) + 1) * cells.shape[1]).astype("<i8"), "Int64", 1)
                    + _array("types", np.full(len(cells), VTK_TYPES[kind], dtype=np.uint8), "UInt8", 1)
                    + "</Cells>")


def write_frame(path: Path, topology: _Topology, displacement: np.ndarray, cell_fields: dict) -> None:
    """One VTU: the reference mesh, point ``displacement`` (mm) and the cell fields."""
    u = np.zeros((topology.n_points, 3))
    u[:, :displacement.shape[1]] = displacement
    point = _float_field("displacement", u)
    cell = "".join(_float_field(name, values) for name, values in cell_fields.items())
    Path(path).write_text(
        '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
        f'header_type="UInt64" compressor="vtkZLibDataCompressor"><UnstructuredGrid><Piece NumberOfPoints="{topology.n_points}" '
        f'NumberOfCells="{topology.n_cells}"><PointData Vectors="displacement">{point}</PointData>'
        f"<CellData>{cell}</CellData>{topology.xml}</Piece></UnstructuredGrid></VTKFile>\n")


def write_time_series(snapshot: Snapshot, folder: Path, stem: str) -> Path:
    """``folder/<stem>_NNN.vtu`` per frame and ``folder/<stem>.pvd`` listing them; returns the PVD."""
    folder = Path(folder)
    (folder / "vtu").mkdir(parents=True, exist_ok=True)
    topology = _Topology(snapshot.mesh)
    entries = []
    for frame in range(snapshot.n_frames):
        name = f"vtu/{stem}_{frame:03d}.vtu"
        write_frame(folder / name, topology, np.asarray(snapshot.displacement[frame]),
                    {k: v[frame] for k, v in snapshot.fields.items()})
        entries.append(f'    <DataSet timestep="{snapshot.t[frame]:.10g}" part="0" file={quoteattr(name)}/>')
    pvd = folder / f"{stem}.pvd"
    pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                   + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return pvd
