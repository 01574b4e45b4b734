"""The size budget (#16 item 9): nodes, DOFs and memory estimated from the geometry before meshing;
a mesh beyond mesh.max_dofs or the machine's memory is refused at once, with the numbers."""

from __future__ import annotations

import time

import pytest

from vlab.fe.space import DisplacementSpace
from vlab.run import build_specimen
from vlab.scene import SceneError, parse_scene


def _block(size=2.5, cell="hex", order=1, dims=(10.0, 8.0, 6.0), **mesh):
    return parse_scene({"name": "b", "specimen": {"shape": "block", "size": list(dims)},
                        "mesh": {"size": size, "cell": cell, "order": order, **mesh},
                        "material": {"model": "linear", "E": 10.0, "nu": 0.3},
                        "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.01, "steps": 1}})


def _shape(shape: dict, size, cell, order, **mesh):
    return parse_scene({"name": "s", "specimen": shape, "mesh": {"size": size, "cell": cell, "order": order, **mesh},
                        "material": {"model": "linear", "E": 10.0, "nu": 0.3},
                        "test": {"kind": "uniaxial", "stretch": 1.01, "steps": 1}})


def _actual_dofs(scene) -> int:
    spec = build_specimen(scene)
    thickness = getattr(spec, "sheet_thickness", None) or 1.0
    return DisplacementSpace.build(spec.mesh, scene.mesh.order, thickness).n_dofs




@pytest.mark.parametrize("cell", ["hex", "tet"])
@pytest.mark.parametrize("order", [1, 2])
def test_the_block_estimate_is_the_mesh_exactly(cell, order):
    from vlab.geometry.budget import estimate

    for scene in (_block(2.5, cell, order), _block(3.0, cell, order, symmetry="quarter")):
        assert estimate(scene).dofs == _actual_dofs(scene)


@pytest.mark.parametrize("cell, order", [("hex", 1), ("tet", 2)])
def test_the_dogbone_estimate_is_within_15_percent_of_its_mesh(cell, order):
    from vlab.geometry.budget import estimate

    for standard in ("ISO 37 2", "ISO 527-2 1A", "ASTM D412 C"):
        for size, extra in ((3.0, {}), (3.0, {"gauge_size": 1.5}), (3.0, {"symmetry": "eighth"})):
            scene = _shape({"shape": "dogbone", "standard": standard}, size, cell, order, **extra)
            ratio = estimate(scene).dofs / _actual_dofs(scene)
            assert 0.85 <= ratio <= 1.15, (standard, size, extra, ratio)


def test_sheet_cruciform_and_imported_estimates_bound_their_meshes_within_stated_factors():
    from pathlib import Path

    from vlab.geometry.budget import estimate
    from vlab.scene import load_scene

    sheet = _shape({"shape": "sheet", "size": [40.0, 10.0], "thickness": 1.0}, 2.0, "quad", 2)
    assert estimate(sheet).dofs == _actual_dofs(sheet)
    specimens = Path(__file__).parent.parent / "specimens"
    for name in ("cruciform-slotted", "cruciform-thinned"):  # breakpoints over-counted: an upper bound
        cruciform = load_scene(specimens / f"{name}.toml")
        ratio = estimate(cruciform).dofs / _actual_dofs(cruciform)
        assert 1.0 <= ratio < 2.5, (name, ratio)
    bar = load_scene(specimens / "mesh-import-bar.toml")
    assert estimate(bar).dofs == _actual_dofs(bar)


def test_a_micron_mesh_on_a_100_mm_block_is_refused_in_under_a_second_with_the_numbers():
    scene = _block(1e-6, dims=(100.0, 100.0, 100.0))
    start = time.perf_counter()
    with pytest.raises(SceneError) as info:
        build_specimen(scene)
    assert time.perf_counter() - start < 1.0
    message = str(info.value)
    assert "mesh.size = 1e-06" in message and "DOFs" in message and "mesh.max_dofs" in message
    assert "1e+24 elements" in message


def test_max_dofs_refuses_a_mesh_above_it_and_the_memory_check_one_the_machine_cannot_hold(monkeypatch):
    import vlab.geometry.budget as budget

    scene = _block(1.0, max_dofs=1000)
    with pytest.raises(SceneError, match=r"more than mesh.max_dofs = 1,000 DOFs"):
        build_specimen(scene)
    monkeypatch.setattr(budget, "available_memory", lambda: 1e8)  # 100 MB free
    with pytest.raises(SceneError, match=r"more than the 0.1 GB of memory available"):
        build_specimen(_block(2.5))


def test_a_huge_mesh_size_ratio_does_not_overflow_the_message():
    scene = _block(1e-300, dims=(100.0, 100.0, 100.0))
    with pytest.raises(SceneError, match=r"10\^9\d\d elements"):
        build_specimen(scene)


def test_above_the_crossover_the_memory_estimate_is_the_linear_iterative_one_and_fits_a_64_cube():
    from vlab.fe.iterative import choose
    from vlab.geometry.budget import BASE_BYTES, estimate

    cube = _block(1.0, dims=(64.0, 64.0, 64.0))
    path = lambda dofs: choose("auto", dofs, "pardiso")  # noqa: E731
    direct, iterative = estimate(cube), estimate(cube, path)
    assert iterative.dofs == direct.dofs == 3 * 65**3 and iterative.iterative and not direct.iterative
    assert iterative.memory_bytes < 10e9 < direct.memory_bytes  # 830k DOFs: ~6 GB without a factor
    half = estimate(_block(1.0, dims=(32.0, 64.0, 64.0)), path)
    slope = (iterative.memory_bytes - BASE_BYTES) / (half.memory_bytes - BASE_BYTES)
    assert slope == pytest.approx(iterative.dofs / half.dofs)  # linear in the DOFs
    assert "CG + AMG, no factorization" in iterative.describe()


def test_a_request_beyond_the_machine_s_memory_exits_2_naming_the_mesh_and_the_estimate(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    import vlab.geometry.budget as budget
    from vlab.cli import app

    scene = tmp_path / "cube.toml"
    scene.write_text('name = "cube"\n[specimen]\nshape = "block"\nsize = [40.0, 40.0, 40.0]\n'
                     '[mesh]\nsize = 1.0\n[material]\nmodel = "neo-hookean"\nE = 10.0\nnu = 0.3\n'
                     '[test]\nkind = "uniaxial"\nstretch = 1.5\nsteps = 10\n')
    monkeypatch.setattr(budget, "available_memory", lambda: 1e9)  # 1 GB free
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["run", str(scene), "--out", str(out), "--no-render"])
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    assert "mesh.size = 1" in text and "206,763 DOFs" in text and "CG + AMG" in text and "1 GB" in text
    assert not out.exists()


def test_every_registered_shape_counts_its_own_mesh_for_the_budget():
    from vlab.geometry.shapes import SHAPES

    assert [name for name, shape in SHAPES.items() if shape.count is None] == []


def test_a_new_shape_gets_a_budget_from_its_registry_entry_alone(monkeypatch):
    """The budget asks the shape's entry, never its name: a shape it has not heard of is counted."""
    from dataclasses import replace

    from vlab.geometry import shapes
    from vlab.geometry.budget import estimate
    from vlab.geometry.counts import MeshCount

    scene = _block(2.5)
    monkeypatch.setitem(shapes.SHAPES, "slab", replace(shapes.SHAPES["block"], name="slab",
                                                       count=lambda spec, mesh: MeshCount(7, 11, 3, "slab rule")))
    est = estimate(replace(scene, specimen=replace(scene.specimen, shape="slab")))
    assert (est.elements, est.nodes, est.dofs, est.how) == (7, 11, 33, "slab rule")
