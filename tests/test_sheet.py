"""The thin sheet in plane stress (2D): homogeneous roller tests against the analytic states, the
elastic constants, clamped grips, plane strain, refusals and bad keys."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.fe.taylor import random_state, taylor_test
from vlab.geometry.sheet import sheet_mesh
from vlab.materials import MODELS, make_material
from vlab.materials.homogeneous import biaxial, plane_strain_uniaxial, uniaxial
from vlab.materials.plane import PlaneStress
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene
from vlab.loading.restraint import unrestrained_modes

SHEET = {
    "name": "test-sheet",
    "specimen": {"shape": "sheet", "size": [20.0, 10.0], "thickness": 0.5},
    "mesh": {"size": 5.0, "order": 1, "cell": "tri"},
    "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
    "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.3, "steps": 3},
}
ELEMENTS = [("tri", 1), ("tri", 2), ("quad", 1), ("quad", 2)]
UNIAXIAL = {"linear": 1.4, "stvk": 1.3, "stvk-volumetric": 1.5, "neo-hookean": 1.8}


def sheet(**sections) -> dict:
    data = copy.deepcopy(SHEET)
    for name, values in sections.items():
        data[name].update(values)
    return data


def _run(**sections):
    result = run_scene(parse_scene(sheet(**sections)))
    assert result.converged, result.history.failure
    return result


def _material(result):
    m = result.scene.material.moduli
    return make_material(result.scene.material.model, m.lmbda, m.mu)


@pytest.mark.parametrize("model", list(MODELS))
@pytest.mark.parametrize("cell,order", ELEMENTS)
def test_uniaxial_roller_sheet_is_the_3d_uniaxial_state(model, cell, order):
    """Plane stress with free edges: P22 = P33 = 0, the 3D homogeneous uniaxial solution."""
    result = _run(material={"model": model}, mesh={"cell": cell, "order": order},
                  test={"stretch": UNIAXIAL[model]})
    mat, c = _material(result), result.curve
    assert result.reference["max_relative_error_x"] < 1e-8
    for s, stress, width, thick in zip(c.stretch[0], c.column("stress"), c.transverse_strain,
                                       c.thickness_strain):
        exact = uniaxial(mat, s)
        assert stress == pytest.approx(exact.P[0, 0], rel=1e-8, abs=1e-12)
        assert 1 + width == pytest.approx(exact.lateral_stretch, rel=1e-8)
        assert 1 + thick == pytest.approx(exact.lateral_stretch, rel=1e-8)  # λ₃ = lateral stretch


@pytest.mark.parametrize("model", list(MODELS))
@pytest.mark.parametrize("cell,order", ELEMENTS)
def test_biaxial_roller_sheet_is_the_3d_biaxial_state(model, cell, order):
    result = _run(material={"model": model}, mesh={"cell": cell, "order": order},
                  test={"kind": "biaxial", "stretch": [1.25, 1.1]})
    mat, c = _material(result), result.curve
    assert max(result.reference["max_relative_error_x"], result.reference["max_relative_error_y"]) < 1e-8
    for sx, sy, px, py, thick in zip(c.stretch[0], c.stretch[1], c.column("stress", 0),
                                     c.column("stress", 1), c.thickness_strain):
        exact = biaxial(mat, sx, sy)
        assert px == pytest.approx(exact.P[0, 0], rel=1e-8, abs=1e-12)
        assert py == pytest.approx(exact.P[1, 1], rel=1e-8, abs=1e-12)
        assert 1 + thick == pytest.approx(exact.lateral_stretch, rel=1e-8)


@pytest.mark.parametrize("model", list(MODELS))
@pytest.mark.parametrize("kind,stretch", [("uniaxial", 1.01), ("biaxial", [1.01, 1.005])])
def test_sheet_recovers_E_and_nu_at_small_strain(model, kind, stretch):
    result = _run(material={"model": model, "E": 7.0, "nu": 0.35}, test={"kind": kind, "stretch": stretch})
    assert result.constants.E == pytest.approx(7.0, rel=0.005)
    assert result.constants.nu == pytest.approx(0.35, rel=0.005)


def test_biaxial_thickness_strain_at_small_strain_is_the_plane_stress_law():
    """ε_t = −ν/(1−ν) (ε_x + ε_y) to first order in the strain."""
    nu = 0.3
    result = _run(test={"kind": "biaxial", "stretch": [1.002, 1.001]}, material={"nu": nu})
    c = result.curve
    for ex, ey, et in zip(c.strain[0], c.strain[1], c.thickness_strain):
        assert et == pytest.approx(-nu / (1 - nu) * (ex + ey), rel=2e-3)


@pytest.mark.parametrize("kind,stretch", [("uniaxial", 1.2), ("biaxial", [1.15, 1.15])])
def test_clamped_sheet_runs_and_is_stiffer_than_rollers(kind, stretch):
    test, square = {"kind": kind, "stretch": stretch}, {"size": [10.0, 10.0]}
    clamped = _run(test=test | {"grips": "clamped"}, mesh={"size": 2.5, "cell": "quad"}, specimen=square)
    roller = _run(test=test, mesh={"size": 2.5, "cell": "quad"}, specimen=square)
    assert clamped.curve.force[0][-1] > 1.005 * roller.curve.force[0][-1]
    assert clamped.reference is None
    if kind == "biaxial":  # a square sheet pulled equally both ways: the two load cells agree
        np.testing.assert_allclose(clamped.curve.force[0], clamped.curve.force[1], rtol=1e-6)


def test_plane_strain_sheet_matches_the_plane_strain_state():
    result = _run(specimen={"plane": "strain"}, mesh={"cell": "quad", "order": 2}, test={"stretch": 1.4})
    mat, c = _material(result), result.curve
    assert result.reference["max_relative_error_x"] < 1e-8
    for s, stress, width in zip(c.stretch[0], c.column("stress"), c.transverse_strain):
        exact = plane_strain_uniaxial(mat, s)
        assert stress == pytest.approx(exact.P[0, 0], rel=1e-8)
        assert 1 + width == pytest.approx(exact.lateral_stretch, rel=1e-8)
    assert np.all(np.array(c.thickness_strain) == 0.0)


def test_stvk_sheet_beyond_its_limit_is_refused_before_solving():
    result = run_scene(parse_scene(sheet(material={"model": "stvk"},
                                         test={"kind": "biaxial", "stretch": [1.8, 1.8]})))
    assert not result.converged
    assert "no admissible state beyond stretch" in result.history.failure.reason


@pytest.mark.parametrize("cell,order", ELEMENTS)
def test_sheet_force_and_stiffness_are_derivatives_of_the_energy(cell, order):
    space = DisplacementSpace.build(sheet_mesh((4.0, 3.0), 1.5, cell), order, thickness=0.7)
    body = HyperelasticBody(space, PlaneStress(make_material("neo-hookean", 1.7, 0.9)))
    u, v = random_state(body, 0.02)
    result = taylor_test(body, u, v, h0=1e-2)
    assert result.energy_order == pytest.approx(2.0, abs=0.1)
    assert result.force_order == pytest.approx(2.0, abs=0.1)


def test_sheet_thickness_scales_forces_not_stresses():
    thin = _run(specimen={"thickness": 0.5})
    thick = _run(specimen={"thickness": 2.0})
    assert thick.curve.force[0][-1] == pytest.approx(4.0 * thin.curve.force[0][-1], rel=1e-12)
    np.testing.assert_allclose(thick.curve.column("stress"), thin.curve.column("stress"), rtol=1e-12)


def test_rigid_modes_of_a_sheet_are_the_two_translations_and_the_rotation():
    X = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    assert unrestrained_modes(X, np.array([0, 4])) == ["translation along y"]  # x held at two heights
    assert len(unrestrained_modes(X, np.array([0, 2]))) == 2  # x held on one line: y and a rotation
    assert len(unrestrained_modes(X, np.array([], dtype=int))) == 3
    assert unrestrained_modes(X, np.array([0, 1, 3])) == []


@pytest.mark.parametrize("specimen,fragment", [
    ({"thickness": -1.0}, "specimen.thickness must be > 0"),
    ({"size": [20.0, 10.0, 1.0]}, "specimen.size must be a list of 2 numbers"),
    ({"size": [20.0, 0.0]}, "specimen.size[1] must be > 0"),
    ({"plane": "shell"}, "specimen.plane must be one of stress, strain"),
])
def test_bad_sheet_keys_name_the_field(specimen, fragment):
    with pytest.raises(SceneError, match=None) as info:
        parse_scene(sheet(specimen=specimen))
    assert fragment in str(info.value)


def test_missing_thickness_and_3d_cells_are_refused():
    data = sheet()
    del data["specimen"]["thickness"]
    with pytest.raises(SceneError, match="missing required key specimen.thickness"):
        parse_scene(data)
    with pytest.raises(SceneError, match="mesh.cell must be one of tri, quad"):
        parse_scene(sheet(mesh={"cell": "hex"}))
    with pytest.raises(SceneError, match="needs a continuum model"):
        parse_scene(sheet(material={"model": "spring-network"}))


def test_sheet_snapshot_and_vtu_are_flat_3d_with_the_full_volume_ratio(tmp_path):
    """The VTU of a sheet: 3D points with z = 0, in-plane displacement, J = det F̄ λ₃ per cell."""
    import pyvista as pv

    from vlab.post.snapshot import take_snapshot
    from vlab.post.vtu import write_time_series

    result = _run(mesh={"cell": "quad", "order": 2}, test={"kind": "biaxial", "stretch": [1.2, 1.1]})
    snap = take_snapshot(result)
    assert snap.displacement.shape[-1] == 3 and np.all(snap.displacement[..., 2] == 0.0)
    assert "thickness" not in snap.marks
    pvd = write_time_series(snap, tmp_path, "sheet")
    grid = pv.read(tmp_path / "vtu" / f"sheet_{snap.n_frames - 1:03d}.vtu")
    assert np.all(grid.points[:, 2] == 0.0)
    np.testing.assert_allclose(grid.point_data["displacement"], snap.displacement[-1])
    exact = biaxial(_material(result), 1.2, 1.1)
    np.testing.assert_allclose(snap.fields["J"][-1], 1.2 * 1.1 * exact.lateral_stretch, rtol=1e-10)
    assert pvd.exists()


def test_2d_mesh_quality_and_checks():
    from vlab.geometry.mesh_check import MeshError, check_mesh
    from vlab.geometry.quality import mesh_quality

    assert mesh_quality(sheet_mesh((4.0, 2.0), 1.0, "quad")).min_quality == pytest.approx(1.0)
    assert mesh_quality(sheet_mesh((4.0, 2.0), 1.0, "tri")).min_quality == pytest.approx(np.sqrt(3) / 2)
    folded = sheet_mesh((2.0, 1.0), 1.0, "quad")
    folded.p[0, 1] = 1.5  # push a corner of the first quad past its neighbours: a bow-tie
    with pytest.raises(MeshError, match="inverted or degenerate"):
        check_mesh(folded)
    flat = sheet_mesh((2.0, 1.0), 1.0, "tri")
    flat.p[1, flat.p[1] > 0.5] = 1e-14  # squash the sheet to a line
    with pytest.raises(MeshError):
        check_mesh(flat)
