import xml.etree.ElementTree as ET

import meshio
import numpy as np
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
