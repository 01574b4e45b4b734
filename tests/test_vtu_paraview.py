"""Outputs ParaView reads right (issue #16, item 11): strictly increasing PVD times with the grip
stretch as field data, order-2 results as quadratic VTK cells with their mid-nodes, and the
Cauchy stress and Green–Lagrange strain tensors per cell; read back with meshio and pyvista."""

import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest
import pyvista as pv

from helpers_scenes import block_scene
from vlab.post.snapshot import take_snapshot
from vlab.post.vtu import write_time_series
from vlab.run import run_scene
from vlab.scene import load_scene

SPECIMENS = Path(__file__).resolve().parents[1] / "specimens"


@pytest.fixture(scope="module")
def load_unload(tmp_path_factory):
    """The plasticity load–unload block (0 → 1.02 → 1): 41 levels + the unloaded frame."""
    result = run_scene(load_scene(SPECIMENS / "block-plasticity-load-unload.toml"))
    assert result.converged
    snap = take_snapshot(result)
    folder = tmp_path_factory.mktemp("pvd")
    return result, snap, write_time_series(snap, folder, "plastic")


def test_a_load_unload_pvd_has_strictly_increasing_times_and_every_dataset_reachable(load_unload):
    result, snap, pvd = load_unload
    steps = [float(d.get("timestep")) for d in ET.parse(pvd).getroot().findall("./Collection/DataSet")]
    assert len(steps) == snap.n_frames and np.all(np.diff(steps) > 0)
    assert max(snap.t) == 1.0 and snap.t[-1] == 0.0  # it does unload (t returns to 0)
    reader = pv.PVDReader(str(pvd))
    assert len(reader.time_values) == snap.n_frames  # ParaView's reader sees all of them
    stretches = []
    for time in reader.time_values:
        reader.set_active_time_value(time)
        grid = reader.read()[0]
        stretches.append(float(grid.field_data["grip_stretch"][0]))
        assert {"cauchy", "green_lagrange", "plastic_strain", "von-mises"} <= set(grid.cell_data)
    np.testing.assert_allclose(stretches, snap.stretch, rtol=0, atol=1e-15)
    assert stretches[-1] == pytest.approx(1.0) and max(stretches) == pytest.approx(1.02)


def test_each_vtu_carries_the_cauchy_and_green_lagrange_tensors_of_the_homogeneous_state(load_unload):
    result, snap, pvd = load_unload
    c = result.curve
    for frame, entry in enumerate(ET.parse(pvd).getroot().findall("./Collection/DataSet")):
        mesh = meshio.read(pvd.parent / entry.get("file"))
        E = np.asarray(mesh.cell_data["green_lagrange"][0]).reshape(-1, 3, 3)
        sigma = np.asarray(mesh.cell_data["cauchy"][0]).reshape(-1, 3, 3)
        lam = snap.stretch[frame]
        np.testing.assert_allclose(E[:, 0, 0], 0.5 * (lam**2 - 1), rtol=1e-8, atol=1e-14)
        np.testing.assert_allclose(sigma, np.swapaxes(sigma, 1, 2), atol=1e-9 * (1 + np.abs(sigma).max()))
        if frame:  # σ_xx = force / current area (roller block: homogeneous)
            i = frame - 1
            area = c.area0[0] * (1 + c.transverse_strain[i]) * (1 + c.thickness_strain[i])
            np.testing.assert_allclose(sigma[:, 0, 0], c.force[0][i] / area, rtol=1e-6)


@pytest.mark.parametrize("cell,vtk_type,meshio_type", [("tet", pv.CellType.QUADRATIC_TETRA, "tetra10"),
                                                       ("hex", pv.CellType.TRIQUADRATIC_HEXAHEDRON, "hexahedron27")])
def test_an_order_2_result_is_written_as_quadratic_cells_with_its_mid_nodes(tmp_path, cell, vtk_type, meshio_type):
    scene = block_scene("neo-hookean", 1.3, cell=cell, size=5.0, steps=2)
    import dataclasses
    scene = dataclasses.replace(scene, mesh=dataclasses.replace(scene.mesh, order=2))
    result = run_scene(scene)
    snap = take_snapshot(result)
    pvd = write_time_series(snap, tmp_path, "q")
    last = tmp_path / "vtu" / f"q_{snap.n_frames - 1:03d}.vtu"
    grid = pv.read(last)
    assert set(grid.celltypes) == {vtk_type}
    assert grid.n_points == result.space.n_nodes and grid.n_cells == result.specimen.mesh.nelements
    np.testing.assert_allclose(grid.points, result.space.node_coordinates)
    np.testing.assert_allclose(grid.point_data["displacement"], result.final_displacement.reshape(-1, 3))
    # straight-sided reference cells: the quadratic cells' volumes are the linear ones
    sizes = grid.compute_cell_sizes(length=False, area=False)["Volume"]
    assert np.abs(sizes).sum() == pytest.approx(1000.0, rel=1e-12)
    assert meshio_type in {b.type for b in meshio.read(last).cells}
    assert pvd.exists()
