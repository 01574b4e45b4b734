"""[specimen] shape = "dogbone" in scenes: standards, explicit dimensions, errors naming the field."""

import pytest

from vlab.scene import DogboneSpecimen, SceneError, parse_scene


def scene(specimen=None, mesh=None, test=None):
    return {
        "name": "d",
        "specimen": {"shape": "dogbone", "standard": "ISO 527-2 1A"} | (specimen or {}),
        "mesh": {"size": 2.5, "cell": "hex"} | (mesh or {}),
        "material": {"model": "linear", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "stretch": 1.01} | (test or {}),
    }


def test_standard_loads_its_dimensions_and_clamped_grips_are_the_default():
    s = parse_scene(scene())
    assert isinstance(s.specimen, DogboneSpecimen)
    d = s.specimen.dimensions
    assert (d.standard, d.overall_length, d.gauge_length, d.width, d.thickness) == ("ISO 527-2 1A", 170, 75, 10, 4)
    assert s.test.grips == "clamped" and s.mesh.min_quality == 0.15 and s.mesh.gauge_size is None


def test_explicit_keys_override_the_standard():
    assert parse_scene(scene({"thickness": 2.0})).specimen.dimensions.thickness == 2.0


def test_explicit_dimensions_without_a_standard():
    dims = {"overall_length": 100.0, "gauge_length": 30.0, "parallel_length": 40.0, "width": 8.0,
            "end_width": 16.0, "fillet_radius": 20.0, "thickness": 2.0, "grip_length": 20.0}
    raw = scene()
    raw["specimen"] = {"shape": "dogbone"} | dims
    d = parse_scene(raw).specimen.dimensions
    assert d.standard == "" and d.outer_radius == 0.0 and d.fillet_radius == 20.0
    del raw["specimen"]["width"]
    with pytest.raises(SceneError, match="missing required key specimen.width"):
        parse_scene(raw)


@pytest.mark.parametrize("specimen, fragment", [
    ({"fillet_radius": 250.0}, "specimen.fillet_radius = 250 mm is larger than possible"),
    ({"gauge_length": 85.0}, "specimen.gauge_length must be <= parallel_length = 80"),
    ({"thickness": -4.0}, "specimen.thickness must be > 0"),
    ({"grip_length": 60.0}, "specimen.grip_length must be <"),
    ({"standard": "ISO 527-2 1Z"}, "specimen.standard must be one of"),
    ({"radius": 3.0}, "unknown key 'radius' in [specimen]"),
])
def test_bad_geometry_is_a_scene_error_naming_the_field(specimen, fragment):
    with pytest.raises(SceneError) as info:
        parse_scene(scene(specimen))
    assert fragment in str(info.value)


@pytest.mark.parametrize("test, fragment", [
    ({"grips": "roller"}, "test.grips must be one of clamped for specimen.shape = 'dogbone'"),
    ({"kind": "biaxial", "stretch": [1.1, 1.1]}, "test.kind must be one of uniaxial for specimen.shape"),
])
def test_dogbone_tests_are_uniaxial_with_clamped_grips(test, fragment):
    with pytest.raises(SceneError, match=fragment.replace("(", r"\(")):
        parse_scene(scene(test=test))


@pytest.mark.parametrize("mesh, fragment", [
    ({"gauge_size": 5.0}, r"mesh.gauge_size must be > 0 and <= 2.5 \(mesh.size\)"),
    ({"min_quality": 1.5}, "mesh.min_quality must be > 0 and < 1"),
])
def test_mesh_keys_are_validated(mesh, fragment):
    with pytest.raises(SceneError, match=fragment):
        parse_scene(scene(mesh=mesh))


def test_gauge_size_is_rejected_for_a_block():
    raw = scene(mesh={"gauge_size": 1.0})
    raw["specimen"] = {"shape": "block", "size": [10.0, 10.0, 10.0]}
    with pytest.raises(SceneError, match="mesh.gauge_size applies to specimen.shape = 'dogbone' or 'cruciform' only"):
        parse_scene(raw)
