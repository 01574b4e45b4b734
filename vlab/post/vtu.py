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

The files are written here directly (VTK XML UnstructuredGrid, inline base64 "binary" arrays,
zlib-compressed, UInt64 headers, little endian), not through pyvista: importing pyvista and VTK cost a
run without renders ~0.3 s of its ~1 s overhead, and a grid copy per frame. pyvista is imported
only for the renders (``reference_grid``).
"""

from __future__ import annotations

import base64
import html
import zlib
from pathlib import Path

import numpy as np

from vlab.post.snapshot import Snapshot

ZLIB_LEVEL = 1  # block16.toml, 11 frames: 8.9 MB raw → 1.3 MB (as pyvista wrote); level 6 took 7× longer
VTK_TYPES = {"triangle": 5, "quad": 9, "tetra": 10, "hexahedron": 12, "wedge": 13,
             "triangle6": 22, "quad9": 28, "tetra10": 24, "hexahedron27": 29}


def quoteattr(text: str) -> str:
    """``text`` as a quoted XML attribute value (&, <, >, ", ' escaped). xml.sax.saxutils'
    quoteattr would do, but importing it imports urllib.request, http and ssl (≈ 0.1 s a run)."""
    return f'"{html.escape(text, quote=True)}"'


def reference_grid(mesh):
    """The scikit-fem mesh (vertices only) as a pyvista grid in VTK node order (renders)."""
    import pyvista as pv
    import skfem.io.meshio

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
    """Points (padded to 3D) and the cell arrays of a mesh, in VTK order, encoded once: the FE
    space's nodes and cells (``vtk`` = (points, meshio cell type, connectivity)) when given, else
    the mesh's vertices."""

    def __init__(self, mesh, vtk: tuple | None = None):
        if vtk is None:
            import skfem.io.meshio  # imports meshio and its ~40 format modules: only for a bare mesh

            m = skfem.io.meshio.to_meshio(mesh)
            (kind, cells), = m.cells_dict.items()
            m_points = m.points
        else:
            m_points, kind, cells = vtk
        points = np.zeros((len(m_points), 3))
        points[:, :m_points.shape[1]] = m_points
        self.n_points, self.n_cells = len(points), len(cells)
        self.xml = ("<Points>" + _array("Points", points.astype("<f8"), "Float64", 3) + "</Points><Cells>"
                    + _array("connectivity", cells.astype("<i8").ravel(), "Int64", 1)
                    + _array("offsets", (np.arange(1, len(cells) + 1) * cells.shape[1]).astype("<i8"), "Int64", 1)
                    + _array("types", np.full(len(cells), VTK_TYPES[kind], dtype=np.uint8), "UInt8", 1)
                    + "</Cells>")


def _field_data(values: dict) -> str:
    """VTK XML FieldData (whole-dataset values: grip stretch, load level, time), ascii."""
    arrays = "".join(f'<DataArray type="Float64" Name={quoteattr(name)} NumberOfTuples="{len(v)}" '
                     f'format="ascii">{" ".join(f"{x:.17g}" for x in v)}</DataArray>'
                     for name, v in values.items())
    return f"<FieldData>{arrays}</FieldData>" if arrays else ""


def write_frame(path: Path, topology: _Topology, displacement: np.ndarray, cell_fields: dict,
                field_data: dict | None = None) -> None:
    """One VTU: the reference mesh, point ``displacement`` (mm), the cell fields ((n,) or (n, k)
    arrays) and ``field_data`` (name -> values)."""
    u = np.zeros((topology.n_points, 3))
    u[:, :displacement.shape[1]] = displacement
    point = _float_field("displacement", u)
    cell = "".join(_float_field(name, values) for name, values in cell_fields.items())
    Path(path).write_text(
        '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
        f'header_type="UInt64" compressor="vtkZLibDataCompressor"><UnstructuredGrid>{_field_data(field_data or {})}<Piece NumberOfPoints="{topology.n_points}" '
        f'NumberOfCells="{topology.n_cells}"><PointData Vectors="displacement">{point}</PointData>'
        f"<CellData>{cell}</CellData>{topology.xml}</Piece></UnstructuredGrid></VTKFile>\n")


def timesteps(snapshot: Snapshot) -> np.ndarray:
    """Strictly increasing PVD time values: the physical time if it increases strictly, else 0, 1, …"""
    time = snapshot.time
    if time is not None and np.all(np.diff(time) > 0.0):
        return np.asarray(time, float)
    return np.arange(snapshot.n_frames, dtype=float)


def _frame_data(snapshot: Snapshot, frame: int) -> dict:
    stretch = snapshot.grip_stretch[frame] if snapshot.grip_stretch is not None else [snapshot.stretch[frame]]
    data = {"grip_stretch": np.asarray(stretch, float), "load_level": [float(snapshot.t[frame])]}
    if snapshot.time is not None:
        data["time"] = [float(snapshot.time[frame])]
    return data


def write_time_series(snapshot: Snapshot, folder: Path, stem: str) -> Path:
    """``folder/<stem>_NNN.vtu`` per frame and ``folder/<stem>.pvd`` listing them; returns the PVD."""
    folder = Path(folder)
    (folder / "vtu").mkdir(parents=True, exist_ok=True)
    topology = _Topology(snapshot.mesh, snapshot.vtk)
    nodal = snapshot.nodal_displacement if snapshot.vtk is not None else None
    entries = []
    for frame, step in enumerate(timesteps(snapshot)):
        name = f"vtu/{stem}_{frame:03d}.vtu"
        cells = {k: v[frame] for k, v in snapshot.fields.items()}
        cells |= {k: v[frame].reshape(len(v[frame]), 9) for k, v in snapshot.tensors.items()}
        write_frame(folder / name, topology, np.asarray((nodal if nodal is not None else snapshot.displacement)[frame]),
                    cells, _frame_data(snapshot, frame))
        entries.append(f'    <DataSet timestep="{step:.17g}" part="0" file={quoteattr(name)}/>')
    pvd = folder / f"{stem}.pvd"
    pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                   + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return pvd
