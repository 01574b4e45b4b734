import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest
import pyvista as pv


def test_vtu_series_reads_back_with_points_and_displacement(comparison):
    for model, out in comparison.by_model.items():
        folder = comparison.folder / model
        pvd = ET.parse(folder / f"{model}.pvd").getroot()
        datasets = pvd.findall("./Collection/DataSet")
        assert len(datasets) == out.snapshot.n_frames
        # quasi-static: the frame index is the time (strictly increasing); t and the stretch are field data
        assert [float(d.get("timestep")) for d in datasets] == list(range(out.snapshot.n_frames))
        for frame, entry in enumerate(datasets):
            grid = pv.read(folder / entry.get("file"))
            assert grid.field_data["load_level"][0] == out.snapshot.t[frame]
            assert np.allclose(grid.field_data["grip_stretch"], out.snapshot.stretch[frame])
            assert grid.n_points == out.snapshot.mesh.nvertices
            assert grid.n_cells == out.snapshot.mesh.nelements
            assert np.allclose(grid.point_data["displacement"], out.snapshot.displacement[frame])
            assert np.allclose(grid.cell_data["von-mises"], out.snapshot.fields["von-mises"][frame])


def test_vtu_is_readable_by_meshio_with_positive_cell_volumes(comparison):
    out = comparison.by_model["stvk"]
    path = comparison.folder / "stvk" / "vtu" / f"stvk_{out.snapshot.n_frames - 1:03d}.vtu"
    mesh = meshio.read(path)
    assert len(mesh.points) == out.snapshot.mesh.nvertices
    assert np.allclose(mesh.point_data["displacement"], out.snapshot.displacement[-1])
    warped = pv.read(path).warp_by_vector("displacement")
    sizes = warped.compute_cell_sizes(length=False, area=False)["Volume"]
    assert np.all(sizes > 0)  # VTK node order right: no inside-out hexahedra
    J = out.snapshot.fields["J"][-1]
    ref_sizes = pv.read(path).compute_cell_sizes(length=False, area=False)["Volume"]
    assert np.allclose(sizes / ref_sizes, J, rtol=1e-6)


def _cases():
    """Every cell type vlab writes: a block (tet, hex), a dogbone (split-hex tets, hexes) and a
    sheet (tri, quad), each at order 1 and 2."""
    dogbone = {"shape": "dogbone", "standard": "ISO 527-2 1A"}
    sheet = {"shape": "sheet", "size": [20.0, 10.0], "thickness": 1.0}
    for name, specimen, cells, mesh in (("block", None, ("tet", "hex"), {}),
                                        ("dogbone", dogbone, ("tet", "hex"), {"size": 8.0}),
                                        ("sheet", sheet, ("tri", "quad"), {"size": 5.0})):
        for cell in cells:
            for order in (1, 2):
                yield name, specimen, mesh | {"cell": cell, "order": order}


@pytest.mark.parametrize("name, specimen, mesh", list(_cases()),
                         ids=[f"{n}-{m['cell']}-p{m['order']}" for n, _, m in _cases()])
def test_every_cell_vlab_writes_has_a_positive_volume_for_pyvista_and_meshio(tmp_path, name, specimen, mesh):
    """VTK's cell sizes (pyvista) of the written VTU, and the signed volume of each tetrahedron's
    corners as meshio reads them, are positive: no inside-out cell (vlab's split hexahedra come
    in both windings; the writer re-winds the negative ones)."""
    from scenes import scene_dict
    from vlab.fe.space import DisplacementSpace
    from vlab.pipeline.prepare import build_specimen
    from vlab.post.vtk_cells import vtk_cells
    from vlab.post.vtu import _Topology, write_frame
    from vlab.scene import parse_scene

    data = scene_dict(mesh=mesh, test={"grips": "clamped"} if name == "dogbone" else {})
    data["specimen"] = specimen or data["specimen"]
    specimen = build_specimen(parse_scene(data))
    space = DisplacementSpace.build(specimen.mesh, mesh["order"], 1.0)
    vtk = vtk_cells(space)
    write_frame(tmp_path / "f.vtu", _Topology(specimen.mesh, vtk), np.zeros((len(vtk[0]), 3)), {})
    grid = pv.read(tmp_path / "f.vtu")
    sizes = grid.compute_cell_sizes(length=False, area=mesh["cell"] in ("tri", "quad"), volume=True)
    size = sizes.cell_data["Area" if mesh["cell"] in ("tri", "quad") else "Volume"]
    assert grid.n_cells == len(vtk[2]) and np.all(size > 0), f"{np.sum(size <= 0)} cells of {len(size)}"
    read = meshio.read(tmp_path / "f.vtu")
    (kind, cells), = read.cells_dict.items()
    if kind.startswith("tetra"):
        x = read.points[cells[:, :4]]
        det = np.einsum("ij,ij->i", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), x[:, 3] - x[:, 0])
        assert np.all(det > 0)
        if kind == "tetra10":  # each mid-node still halves its (re-wound) edge
            edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
            for k, (a, b) in enumerate(edges):
                assert np.allclose(read.points[cells[:, 4 + k]], 0.5 * (x[:, a] + x[:, b]))
