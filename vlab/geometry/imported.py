"""A user's mesh as a specimen: Gmsh .msh (v2 or v4) or VTK .vtu read with meshio, grips on named
regions, gauge marks and cross-section area from the scene.

Named regions (looked up in this order):
- Gmsh physical groups: a physical name (``field_data``: name -> [tag, dim]) selects the cells of
  that dimension whose ``gmsh:physical`` tag matches — e.g. the surface triangles of a grip face;
- meshio cell sets of that name;
- a point-data array of that name (its nonzero points) or a cell-data array (the nodes of its
  nonzero cells) — the way a .vtu carries regions.
The region's nodes are the grip. The volume cells are the mesh's tetrahedra (P1; P2 from
``[mesh] order = 2``) or hexahedra; nodes no volume cell uses are dropped. The mesh is turned so
its loading axis becomes x (a cyclic permutation of the axes, which keeps orientation): marks
given in the file's coordinates are turned the same way. Of the two grips the one lower along the
loading axis holds, the other moves; the grip separation is the gap between them along the axis.
"""

from __future__ import annotations

import contextlib
import io
import logging
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import skfem

from vlab import fields
from vlab.geometry.locate import locate
from vlab.fields import SceneError
from vlab.geometry.counts import MeshCount
from vlab.geometry.shape import Shape
from vlab.geometry.specimen import GaugeMarks, Grip, Specimen

log = logging.getLogger(__name__)

MESH_SUFFIXES = (".msh", ".vtu")
_DIM = {"vertex": 0, "line": 1, "line3": 1, "triangle": 2, "triangle6": 2, "quad": 2, "quad8": 2, "quad9": 2,
        "tetra": 3, "tetra10": 3, "hexahedron": 3, "hexahedron20": 3, "hexahedron27": 3}
_VOLUME = {"tetra": ("tet", 4), "tetra10": ("tet", 4), "hexahedron": ("hex", 8)}
# meshio (VTK) hexahedron corner order -> scikit-fem MeshHex corner order
_HEX_FROM_VTK = np.array([0, 4, 3, 1, 7, 5, 2, 6])


class MeshImportError(SceneError):
    """The mesh file cannot serve as a specimen; ``field`` names the scene key to fix (a SceneError:
    the CLI's exit 2 and a study's "invalid" row, wherever it is raised)."""

    def __init__(self, field: str, message: str):
        super().__init__(f"{field} {message}")
        self.field = field


@dataclass(frozen=True)
class ImportedMesh:
    """Nodes (n, 3), volume cells and named node sets of a mesh file."""

    points: np.ndarray
    cell: str  # "tet" | "hex"
    cells: np.ndarray  # (e, 4) or (e, 8), scikit-fem corner order
    regions: dict[str, np.ndarray]  # name -> node indices

    @property
    def names(self) -> list[str]:
        return sorted(self.regions)


def read_mesh(path: Path) -> ImportedMesh:
    """Read a .msh or .vtu file with meshio; MeshImportError naming specimen.file if it is unusable."""
    import meshio

    if path.suffix.lower() not in MESH_SUFFIXES:
        raise MeshImportError("specimen.file", f"must be a Gmsh .msh or a .vtu file, got {path.name!r}")
    if not path.is_file():
        raise MeshImportError("specimen.file", f"{str(path)!r} does not exist")
    said = io.StringIO()  # meshio prints its complaints (and then calls sys.exit on some files)
    try:
        with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
            m = meshio.read(path)
    except (Exception, SystemExit) as exc:  # meshio raises many types for malformed files
        text = " ".join(said.getvalue().split())
        detail = text or (f"{type(exc).__name__}: {exc}" if not isinstance(exc, SystemExit) else "unreadable")
        raise MeshImportError("specimen.file", f"{str(path)!r} cannot be read as a mesh by meshio "
                              f"({detail})") from None
    if not np.all(np.isfinite(m.points)):
        bad = int(np.flatnonzero(~np.isfinite(m.points).all(axis=1))[0])
        raise MeshImportError("specimen.file", f"{str(path)!r}: node {bad} has a non-finite coordinate "
                              f"{m.points[bad].tolist()}")
    volume = [(b.type, b.data) for b in m.cells if b.type in _VOLUME]
    kinds = {_VOLUME[t][0] for t, _ in volume}
    if len(kinds) != 1:
        found = sorted({b.type for b in m.cells})
        raise MeshImportError("specimen.file", f"must hold tetrahedra or hexahedra (one kind), found cell "
                           f"types {found}")
    cell = kinds.pop()
    cells = np.concatenate([data[:, :_VOLUME[t][1]] for t, data in volume]).astype(np.int64)
    if cell == "hex":
        cells = cells[:, _HEX_FROM_VTK]
    regions = _regions(m)
    used = np.unique(cells)
    new_id = np.full(len(m.points), -1, dtype=np.int64)
    new_id[used] = np.arange(len(used))
    points = np.zeros((len(used), 3))
    points[:, :m.points.shape[1]] = m.points[used]
    regions = {k: new_id[v][new_id[v] >= 0] for k, v in regions.items()}
    return ImportedMesh(points, cell, new_id[cells], {k: v for k, v in regions.items() if len(v)})


def _regions(m) -> dict[str, np.ndarray]:
    """name -> node indices (original numbering), module docstring."""
    out: dict[str, set] = {}
    physical = m.cell_data.get("gmsh:physical")
    for name, (tag, dim) in ((k, v[:2]) for k, v in m.field_data.items()):
        if physical is None:
            break
        for block, tags in zip(m.cells, physical):
            if _DIM.get(block.type) == int(dim):
                out.setdefault(name, set()).update(block.data[np.asarray(tags) == tag].ravel().tolist())
    for name, per_block in m.cell_sets.items():
        for block, idx in zip(m.cells, per_block):
            if idx is not None and len(idx):
                out.setdefault(name, set()).update(block.data[np.asarray(idx)].ravel().tolist())
    for name, values in m.point_data.items():
        if not name.startswith("gmsh:") and np.asarray(values).ndim == 1:
            out.setdefault(name, set()).update(np.flatnonzero(np.asarray(values)).tolist())
    for name, per_block in m.cell_data.items():
        if name.startswith("gmsh:"):
            continue
        for block, values in zip(m.cells, per_block):
            values = np.asarray(values)
            if values.ndim == 1:
                out.setdefault(name, set()).update(block.data[values != 0].ravel().tolist())
    return {k: np.array(sorted(v), dtype=np.int64) for k, v in out.items()}


@dataclass(frozen=True)
class MeshImport:
    """What a scene says about an imported mesh (file coordinates, mm)."""

    file: Path
    grips: tuple[str, str]  # region names
    axis: int  # loading axis in the file: 0, 1, 2
    gauge_marks: tuple[tuple[float, ...], tuple[float, ...]]
    transverse_marks: tuple[tuple[float, ...], tuple[float, ...]]
    thickness_marks: tuple[tuple[float, ...], tuple[float, ...]]
    area: float


def _turn(points: np.ndarray, axis: int) -> np.ndarray:
    """Cyclic axis permutation that brings ``axis`` to x."""
    return np.asarray(points, float)[..., [(axis + k) % 3 for k in range(3)]]


def _region_selector(X: np.ndarray, nodes: np.ndarray, mesh: skfem.Mesh, tol: float):
    """Selector of every DOF node of the mesh entities (vertices, edges, facets, cells) whose
    vertices all lie in the region: what the order-2 basis places on them. An order-2 DOF sits
    at its entity's vertex mean (the edge midpoint; the centre of a hexahedron's bilinear face
    and of its trilinear cell, the 27-node hexahedron's face and volume nodes), so a grip face
    holds all of its facet DOFs, and a volume region all of its cells' DOFs."""
    inside = np.zeros(mesh.nvertices, bool)
    inside[nodes] = True
    points = [X[nodes]]
    for entities in (mesh.edges, mesh.facets, mesh.t):
        held = entities[:, np.all(inside[entities], axis=0)]
        points.append(X[held].mean(axis=0))  # (k, n_vertices of the entity) -> vertex means
    from scipy.spatial import cKDTree  # ~0.1 s to import: paid only where it is used

    tree = cKDTree(np.vstack(points))
    return lambda Y: tree.query(np.asarray(Y, float), distance_upper_bound=tol)[0] <= tol


def imported_specimen(spec: MeshImport, data: ImportedMesh) -> Specimen:
    """The specimen of an imported mesh (module docstring)."""
    X = _turn(data.points, spec.axis)
    mesh = (skfem.MeshTet if data.cell == "tet" else skfem.MeshHex)(
        np.ascontiguousarray(X.T), np.ascontiguousarray(data.cells.T))
    extent = float(np.linalg.norm(X.max(axis=0) - X.min(axis=0)))
    tol = 1e-9 * extent
    grips = sorted(spec.grips, key=lambda name: X[data.regions[name], 0].mean())
    fixed, moving = (data.regions[name] for name in grips)
    gap = float(X[moving, 0].min() - X[fixed, 0].max())
    if not gap > 0:
        raise MeshImportError("specimen.grips", f"regions {grips[0]!r} and {grips[1]!r} overlap along the loading "
                           f"axis; they must be apart (gap {gap:g} mm)")
    marks = {key: GaugeMarks(*(tuple(_turn(p, spec.axis)) for p in pair)) for key, pair in
             (("gauge", spec.gauge_marks), ("transverse", spec.transverse_marks),
              ("thickness", spec.thickness_marks))}
    return Specimen(
        shape="mesh",
        mesh=mesh,
        grips=(Grip(grips[0], 0, -1, _region_selector(X, fixed, mesh, tol)),
               Grip(grips[1], 0, +1, _region_selector(X, moving, mesh, tol))),
        grip_separation={0: gap},
        extensometers={0: marks["gauge"]},
        transverse={0: marks["transverse"]},
        thickness=marks["thickness"],
        area0={0: spec.area},
        length_scale=extent,
    )


# --- the scene's [specimen] shape = "mesh" ----------------------------------------------------

@dataclass(frozen=True)
class MeshFileSpecimen:
    shape: str
    spec: MeshImport  # file (absolute), grip region names, loading axis, marks, area
    data: ImportedMesh = field(compare=False, repr=False)  # the mesh as read at validation

    @property
    def extent(self) -> np.ndarray:
        return self.data.points.max(axis=0) - self.data.points.min(axis=0)

    @property
    def length(self) -> float:
        return float(self.extent[self.spec.axis])

    @property
    def max_dimension(self) -> float:
        return float(self.extent.max())


SCENE_DIR: ContextVar[Path] = ContextVar("scene_base_dir", default=Path("."))  # resolves specimen.file
_AXES = ("x", "y", "z")


def _marks(t: fields.Table, key: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    v = t.get(key)
    if not isinstance(v, list) or len(v) != 2:
        raise SceneError(f"{t.field(key)} must be two points [[x, y, z], [x, y, z]] in the mesh file's "
                         f"coordinates (mm), got {fields.show(v)}")
    return tuple(fields.vector(f"{t.field(key)}[{i}]", p, 3, "[x, y, z] in mm") for i, p in enumerate(v))  # type: ignore


def _parse_mesh_file(t: fields.Table) -> MeshFileSpecimen:
    """``file`` (.msh or .vtu, relative to the scene file), ``grips = {a = "name", b = "name"}``
    (two named regions of the file), ``axis`` (loading axis of the file, default "x"),
    ``gauge_marks``, ``transverse_marks``, ``thickness_marks`` (two points each) and ``area`` (mm²,
    the section the nominal stress divides by)."""
    name = t.get("file")
    if not isinstance(name, str) or not name:
        raise SceneError(f"{t.field('file')} must be a path to a .msh or .vtu file, got {fields.show(name)}")
    path = Path(name) if Path(name).is_absolute() else SCENE_DIR.get() / name
    try:
        data = read_mesh(path)
    except MeshImportError as exc:
        raise SceneError(f"{exc}") from None
    return mesh_file_specimen(t, path, data)


def mesh_file_specimen(t: fields.Table, path: Path, data: ImportedMesh) -> MeshFileSpecimen:
    """The specimen of a mesh read from ``path`` (a mesh file, or Gmsh's mesh of a CAD file)."""
    grips = t.get("grips")
    if not isinstance(grips, dict) or len(grips) != 2 or not all(isinstance(v, str) for v in grips.values()):
        raise SceneError(f"{t.field('grips')} must be a table of two region names, e.g. {{left = \"grip_left\", "
                         f"right = \"grip_right\"}}, got {fields.show(grips)}")
    for key, region in grips.items():
        if region not in data.regions:
            raise SceneError(f"{t.field('grips')}.{key} = {region!r} is not a region of {path.name}; regions "
                             f"found: {', '.join(data.names) or 'none'}")
    spec = MeshImport(file=path.resolve(), grips=tuple(grips.values()),  # type: ignore[arg-type]
                      axis=_AXES.index(t.choice("axis", _AXES, default="x")),
                      gauge_marks=_marks(t, "gauge_marks"), transverse_marks=_marks(t, "transverse_marks"),
                      thickness_marks=_marks(t, "thickness_marks"), area=t.number("area", gt=0))
    _check_marks_inside(t, spec, data)
    return MeshFileSpecimen(shape="mesh", spec=spec, data=data)


def _check_marks_inside(t: fields.Table, spec: MeshImport, data: ImportedMesh) -> None:
    """Every mark where the instruments will find it (the same search, vlab.geometry.locate)."""
    mesh = (skfem.MeshTet if data.cell == "tet" else skfem.MeshHex)(
        np.ascontiguousarray(data.points.T), np.ascontiguousarray(data.cells.T))
    basis = skfem.CellBasis(mesh, mesh.elem())
    for key in ("gauge_marks", "transverse_marks", "thickness_marks"):
        for point in getattr(spec, key):
            try:
                locate(basis, np.asarray(point, dtype=float)[:, None])
            except ValueError:
                raise SceneError(f"{t.field(key)}: point {list(point)} lies outside the mesh of "
                                 f"{spec.file.name} (bounding box {data.points.min(axis=0).tolist()} to "
                                 f"{data.points.max(axis=0).tolist()})") from None


MESH_FILE_KEYS = ("file", "grips", "axis", "gauge_marks", "transverse_marks", "thickness_marks", "area")

def count_imported(spec, mesh) -> MeshCount:
    """The file's own nodes and cells; order 2 adds one node per edge (tetrahedra: the unique edges
    counted; hexahedra: ≈ 3 edges per vertex) and, for hexahedra, per face (≈ 3 per cell) and cell."""
    data, order = spec.data, mesh.order
    nodes, cells = len(data.points), len(data.cells)
    if order == 1:
        return MeshCount(cells, nodes, 3, "the file's own cells")
    if data.cell == "hex":
        return MeshCount(cells, nodes + 3 * nodes + 3 * cells + cells, 3, "the file's own cells")
    pairs = (0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)
    edges = np.unique(np.sort(np.concatenate([data.cells[:, list(p)] for p in pairs]), axis=1), axis=0)
    return MeshCount(cells, nodes + len(edges), 3, "the file's own cells")


SHAPE = Shape("mesh", MESH_FILE_KEYS, _parse_mesh_file, lambda spec, mesh, gauge: imported_specimen(spec.spec, spec.data),
              tests={"uniaxial": ("clamped",)}, count=count_imported,
              doc="a user's mesh file (Gmsh .msh or .vtu) with named grips",
              gauge_from="specimen.gauge_marks (two points in the file's coordinates)")
