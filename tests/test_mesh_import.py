"""[specimen] shape = "mesh": a user's Gmsh .msh or .vtu file with named grip regions. The files are
written here with meshio from vlab's own block mesh, so the imported run must read exactly what the
native block run reads."""

import tomllib
from pathlib import Path

import meshio
import numpy as np
import pytest

from vlab.geometry.block import block_specimen
from vlab.run import run_scene
from vlab.scene import SceneError, load_scene, parse_scene

SIZE = (20.0, 5.0, 2.0)
MARKS = {"gauge_marks": [[5.0, 2.5, 2.0], [15.0, 2.5, 2.0]],
         "transverse_marks": [[10.0, 0.0, 1.0], [10.0, 5.0, 1.0]],
         "thickness_marks": [[10.0, 2.5, 0.0], [10.0, 2.5, 2.0]]}
SPECIMENS = Path(__file__).resolve().parents[1] / "specimens"


def end_faces(mesh, length):
    """Boundary facets on x = 0 and x = length (node ids, scikit-fem order)."""
    facets = mesh.facets[:, mesh.boundary_facets()]
    x = mesh.p[0, facets].mean(axis=0)
    return facets[:, np.abs(x) < 1e-9].T, facets[:, np.abs(x - length) < 1e-9].T


def write_msh(path: Path, cell="tet") -> Path:
    """A Gmsh 2.2 file: the block's tetrahedra, its end faces as physical surfaces."""
    mesh = block_specimen(SIZE, 1.25, cell).mesh
    left, right = end_faces(mesh, SIZE[0])
    cells = [("triangle", left), ("triangle", right), ("tetra", mesh.t.T)]
    tags = [np.full(len(left), 1), np.full(len(right), 2), np.full(mesh.nelements, 3)]
    meshio.write(path, meshio.Mesh(mesh.p.T, cells, cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
                                   field_data={"grip_left": np.array([1, 2]), "grip_right": np.array([2, 2]),
                                               "body": np.array([3, 3])}),
                 file_format="gmsh22", binary=False)
    return path


def write_msh41(path: Path) -> Path:
    """The same as write_msh in the Gmsh 4.1 ASCII format, written by hand (entities carry the
    physical tags): two surfaces (the end faces) and one volume."""
    mesh = block_specimen(SIZE, 1.25, "tet").mesh
    left, right = end_faces(mesh, SIZE[0])
    lo, hi = mesh.p.min(axis=1), mesh.p.max(axis=1)
    box = " ".join(f"{v:g}" for v in (*lo, *hi))
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat",
             "$PhysicalNames", "3", '2 1 "grip_left"', '2 2 "grip_right"', '3 3 "body"', "$EndPhysicalNames",
             "$Entities", "0 0 2 1", f"1 {box} 1 1 0", f"2 {box} 1 2 0", f"1 {box} 1 3 0", "$EndEntities",
             "$Nodes", f"1 {mesh.nvertices} 1 {mesh.nvertices}", f"3 1 0 {mesh.nvertices}"]
    lines += [str(i + 1) for i in range(mesh.nvertices)]
    lines += [" ".join(f"{c:.17g}" for c in x) for x in mesh.p.T]
    lines += ["$EndNodes"]
    blocks = [(2, 1, 2, left), (2, 2, 2, right), (3, 1, 4, mesh.t.T)]
    total = sum(len(b[3]) for b in blocks)
    lines += ["$Elements", f"3 {total} 1 {total}"]
    tag = 1
    for dim, entity, kind, conn in blocks:
        lines.append(f"{dim} {entity} {kind} {len(conn)}")
        for row in conn:
            lines.append(" ".join(map(str, [tag, *(row + 1)])))
            tag += 1
    lines += ["$EndElements"]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_vtu(path: Path) -> Path:
    """A .vtu of the block's hexahedra (VTK corner order) with the grips as point-data arrays."""
    mesh = block_specimen(SIZE, 1.25, "hex").mesh
    vtk_from_skfem = [0, 3, 6, 2, 1, 5, 7, 4]  # inverse of vlab.geometry.imported._HEX_FROM_VTK
    x = mesh.p[0]
    meshio.write(path, meshio.Mesh(mesh.p.T, [("hexahedron", mesh.t.T[:, vtk_from_skfem])],
                                   point_data={"clamp_a": (np.abs(x) < 1e-9).astype(np.int32),
                                               "clamp_b": (np.abs(x - SIZE[0]) < 1e-9).astype(np.int32)}))
    return path


def mesh_scene(file, grips, **specimen):
    return {"name": "m", "specimen": {"shape": "mesh", "file": str(file), "grips": grips, "area": 10.0}
            | MARKS | specimen, "mesh": {}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
            "test": {"kind": "uniaxial", "stretch": 1.05, "steps": 2}}


def native_block(cell):
    """The same block, clamped at its end faces, with the same marks (reference run)."""
    return parse_scene({"name": "b", "specimen": {"shape": "block", "size": list(SIZE)},
                        "mesh": {"size": 1.25, "cell": cell},
                        "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
                        "test": {"kind": "uniaxial", "grips": "clamped", "stretch": 1.05, "steps": 2},
                        "measure": {"gauge_length": 10.0}})


@pytest.mark.parametrize("fmt", ["msh", "msh41", "vtu"])
def test_imported_mesh_reads_what_the_native_block_reads(fmt, tmp_path):
    if fmt.startswith("msh"):
        write = write_msh if fmt == "msh" else write_msh41
        scene = parse_scene(mesh_scene(write(tmp_path / "bar.msh"), {"left": "grip_left", "right": "grip_right"}))
        cell = "tet"
    else:
        scene = parse_scene(mesh_scene(write_vtu(tmp_path / "bar.vtu"), {"a": "clamp_b", "b": "clamp_a"}))
        cell = "hex"
    assert scene.mesh.cell == cell
    imported, native = run_scene(scene), run_scene(native_block(cell))
    assert imported.converged and native.converged
    assert imported.specimen.grip_separation[0] == pytest.approx(20.0)
    for a, b in ((imported.curve.force[0], native.curve.force[0]), (imported.curve.strain[0], native.curve.strain[0]),
                 (imported.curve.transverse_strain, native.curve.transverse_strain)):
        np.testing.assert_allclose(a, b, rtol=1e-9)
    assert imported.constants.E == pytest.approx(native.constants.E, rel=1e-9)


def test_loading_axis_turns_the_mesh(tmp_path):
    """The same bar stood up along z: the file's coordinates turned, the readings unchanged."""
    mesh = block_specimen(SIZE, 1.25, "tet").mesh
    left, right = end_faces(mesh, SIZE[0])
    turned = mesh.p.T[:, [1, 2, 0]]  # file (x, y, z) = block (y, z, x): loading along z
    path = tmp_path / "up.msh"
    tags = [np.full(len(left), 1), np.full(len(right), 2), np.full(mesh.nelements, 3)]
    meshio.write(path, meshio.Mesh(turned, [("triangle", left), ("triangle", right), ("tetra", mesh.t.T)],
                                   cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
                                   field_data={"bottom": np.array([1, 2]), "top": np.array([2, 2])}),
                 file_format="gmsh22", binary=False)
    marks = {k: [[p[1], p[2], p[0]] for p in v] for k, v in MARKS.items()}
    up = run_scene(parse_scene(mesh_scene(path, {"a": "top", "b": "bottom"}, axis="z", **marks)))
    flat = run_scene(parse_scene(mesh_scene(write_msh(tmp_path / "flat.msh"), {"l": "grip_left", "r": "grip_right"})))
    assert up.converged and flat.converged
    np.testing.assert_allclose(up.specimen.mesh.p, flat.specimen.mesh.p, atol=1e-12)
    np.testing.assert_allclose(up.curve.force[0], flat.curve.force[0], rtol=1e-9)
    np.testing.assert_allclose(up.curve.transverse_strain, flat.curve.transverse_strain, rtol=1e-9)


def test_missing_region_names_the_ones_found(tmp_path):
    path = write_msh(tmp_path / "bar.msh")
    with pytest.raises(SceneError, match=r"specimen.grips.right = 'grip_rigth' is not a region of bar.msh; "
                                         r"regions found: body, grip_left, grip_right"):
        parse_scene(mesh_scene(path, {"left": "grip_left", "right": "grip_rigth"}))


@pytest.mark.parametrize("change, mesh, fragment", [
    ({"file": "nowhere.msh"}, {}, "specimen.file '"),
    ({"file": "part.stl"}, {}, "specimen.file must be a Gmsh .msh or a .vtu file"),
    ({"gauge_marks": [[5.0, 2.5, 2.0], [25.0, 2.5, 2.0]]}, {}, "specimen.gauge_marks: point [25.0, 2.5, 2.0] lies "
                                                                "outside the mesh"),
    ({"area": -1.0}, {}, "specimen.area must be > 0"),
    ({}, {"symmetry": "half"}, "mesh.symmetry must be 'none' for specimen.shape = 'mesh'"),
    ({}, {"size": 2.0}, "mesh.size does not apply to specimen.shape = 'mesh'"),
    ({}, {"cell": "hex"}, "mesh.cell must be 'tet'"),
])
def test_bad_import_requests_name_the_field(change, mesh, fragment, tmp_path):
    raw = mesh_scene(write_msh(tmp_path / "bar.msh"), {"left": "grip_left", "right": "grip_right"})
    raw["specimen"] |= change
    raw["mesh"] = mesh
    with pytest.raises(SceneError) as info:
        parse_scene(raw)
    assert fragment in str(info.value)


def test_the_committed_mesh_scene_resolves_its_file_next_to_it():
    scene = load_scene(SPECIMENS / "mesh-import-bar.toml")
    assert scene.specimen.spec.file == (SPECIMENS / "meshes" / "bar.msh").resolve()
    assert tomllib.loads((SPECIMENS / "mesh-import-bar.toml").read_text())["specimen"]["file"] == "meshes/bar.msh"


def test_compare_rebuilds_the_scene_with_its_file_from_any_folder(tmp_path, monkeypatch):
    from vlab.compare import scene_for_model

    scene = load_scene(SPECIMENS / "mesh-import-bar.toml")
    monkeypatch.chdir(tmp_path)  # the relative file must still resolve next to the scene file
    other = scene_for_model(scene, "linear")
    assert other.material.model == "linear" and other.specimen.spec.file == scene.specimen.spec.file
