"""``shape = "cad"``: a specimen drawn in CAD (Gmsh .geo, STEP, BREP; vlab.geometry.cad), meshed
by Gmsh at ``mesh.size`` once the [mesh] table is read, then the same specimen as an imported mesh
(grips, marks, area, clamped uniaxial test, vlab's mesh checks). Grips: two physical-group names
or boxes ``{min = [x, y, z], max = [x, y, z]}`` (file coordinates, mm)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.shape import Shape

CAD_KEYS = ("file", "grips", "axis", "gauge_marks", "transverse_marks", "thickness_marks", "area")


@dataclass(frozen=True)
class CadSpecimen:
    """The [specimen] table of a CAD specimen before meshing (what Gmsh reported of the file)."""

    shape: str
    file: Path
    table: dict  # the raw [specimen] table, parsed again as an imported mesh once meshed
    extent: np.ndarray  # bounding box of the file's volumes, mm
    cells: tuple = ("tet",)  # Gmsh meshes it in tetrahedra

    @property
    def max_dimension(self) -> float:
        return float(self.extent.max())


def _grips(t: fields.Table, names: list[str], file: Path) -> dict:
    grips = t.get("grips")
    if not isinstance(grips, dict) or len(grips) != 2:
        raise SceneError(f"{t.field('grips')} must be a table of two grips, each a physical-group name or a box "
                         f"{{min = [x, y, z], max = [x, y, z]}}, got {fields.show(grips)}")
    for key, value in grips.items():
        if isinstance(value, str):
            if value not in names:
                raise SceneError(f"{t.field('grips')}.{key} = {value!r} is not a physical group of {file.name}; "
                                 f"groups found: {', '.join(names) or 'none'}")
        elif isinstance(value, dict) and set(value) == {"min", "max"}:
            lo = fields.vector(f"{t.field('grips')}.{key}.min", value["min"], 3, "[x, y, z] in mm")
            hi = fields.vector(f"{t.field('grips')}.{key}.max", value["max"], 3, "[x, y, z] in mm")
            if not all(a < b for a, b in zip(lo, hi)):
                raise SceneError(f"{t.field('grips')}.{key}: min {list(lo)} must be below max {list(hi)} on every axis")
        else:
            raise SceneError(f"{t.field('grips')}.{key} must be a physical-group name or a box "
                             f"{{min = [x, y, z], max = [x, y, z]}}, got {fields.show(value)}")
    return grips


def parse_cad(t: fields.Table, base_dir: Path) -> CadSpecimen:
    from vlab.geometry.cad import inspect_cad
    from vlab.geometry.imported import MeshImportError

    name = t.get("file")
    if not isinstance(name, str) or not name:
        raise SceneError(f"{t.field('file')} must be a path to a .geo, .step, .stp or .brep file, got "
                         f"{fields.show(name)}")
    path = Path(name) if Path(name).is_absolute() else base_dir / name
    try:
        names, lo, hi = inspect_cad(path)
    except MeshImportError as exc:
        raise SceneError(f"{exc}") from None
    _grips(t, names, path)
    for key in CAD_KEYS:
        if key not in ("grips", "axis") and key not in t.raw:
            raise SceneError(f"missing required key {t.field(key)}")
    return CadSpecimen(shape="cad", file=path.resolve(), table=dict(t.raw), extent=np.asarray(hi) - np.asarray(lo))


def meshed(specimen: CadSpecimen, size: float):
    """The CAD specimen meshed by Gmsh at ``size``: a MeshFileSpecimen with shape "cad"."""
    from dataclasses import replace

    from vlab.geometry.cad import add_box_regions, mesh_cad
    from vlab.geometry.imported import MeshImportError
    from vlab.geometry.imported import mesh_file_specimen

    try:
        data = mesh_cad(specimen.file, size)
    except MeshImportError as exc:
        raise SceneError(f"{exc}") from None
    grips = specimen.table["grips"]
    boxes = {f"box:{key}": (v["min"], v["max"]) for key, v in grips.items() if isinstance(v, dict)}
    data = add_box_regions(data, boxes)
    table = dict(specimen.table, grips={k: (v if isinstance(v, str) else f"box:{k}") for k, v in grips.items()})
    out = mesh_file_specimen(fields.Table("specimen", table, ("shape",) + CAD_KEYS), specimen.file, data)
    return replace(out, shape="cad")


def _parse(t: fields.Table) -> CadSpecimen:
    from vlab.geometry.imported import SCENE_DIR

    return parse_cad(t, SCENE_DIR.get())


def _build(spec, mesh, gauge_length):
    from vlab.geometry.imported import imported_specimen

    return imported_specimen(spec.spec, spec.data)  # meshed by Gmsh when the scene was read (meshed)


def _count(spec, mesh):
    from vlab.geometry.imported import count_imported

    return count_imported(spec, mesh)  # meshed by Gmsh when the scene was read: the file's own cells


SHAPE = Shape("cad", CAD_KEYS, _parse, _build, tests={"uniaxial": ("clamped",)}, count=_count,
              doc="a specimen drawn in CAD (Gmsh .geo, STEP, BREP), meshed by Gmsh (the cad extra)",
              gauge_from="specimen.gauge_marks (two points in the file's coordinates)")
