import copy
import dataclasses
import math

from pathlib import Path

import pytest

from vlab.moduli import from_pair
from vlab.scene import (BlockSpecimen, MeasureSpec, MeshSpec, Scene, SceneError, SolverSpec,
                        TestSpec, apply_overrides, load_scene, parse_scene)

EXAMPLE = '''\
name = "block-nh"            # required
description = "a neo-Hookean block"
[specimen]
shape = "block"
size = [10.0, 10.0, 10.0]
[mesh]
size = 2.5
order = 1
cell = "tet"
[material]
model = "neo-hookean"
E = 10.0
nu = 0.3
root = "plus"
[test]
kind = "uniaxial"
grips = "roller"
stretch = 1.5
steps = 10
[measure]
modulus_window = [0.0005, 0.0025]
gauge_length = 5.0
fit = "regression"
[solver]
rtol = 1e-8
max_iterations = 25
max_cutbacks = 8
'''

MINIMAL = {
    "name": "min",
    "specimen": {"shape": "block", "size": [20, 5, 2]},
    "mesh": {"size": 1},
    "material": {"model": "linear", "E": 100, "nu": 0.25},
    "test": {"kind": "uniaxial", "stretch": 1.1},
}


@pytest.fixture
def example_file(tmp_path):
    path = tmp_path / "block-nh.toml"
    path.write_text(EXAMPLE, encoding="utf-8")
    return path


def test_example_parses(example_file):
    s = load_scene(example_file)
    assert isinstance(s, Scene)
    assert s.name == "block-nh" and s.description == "a neo-Hookean block"
    assert s.specimen == BlockSpecimen(shape="block", size=(10.0, 10.0, 10.0))
    assert s.mesh == MeshSpec(size=2.5, order=1, cell="tet")
    assert s.material.model == "neo-hookean"
    assert s.material.moduli == from_pair({"E": 10.0, "nu": 0.3})
    assert s.material.given == {"E": 10.0, "nu": 0.3}
    assert s.test == TestSpec(kind="uniaxial", grips="roller", stretch=(1.5,), steps=10)
    assert s.measure == MeasureSpec(modulus_window=(0.0005, 0.0025), gauge_length=5.0, fit="regression")
    assert s.solver == SolverSpec(rtol=1e-8, max_iterations=25, max_cutbacks=8)
    assert s.source["material"]["root"] == "plus"
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.name = "other"


def test_defaults():
    s = parse_scene(MINIMAL)
    assert s.description == ""
    assert s.specimen.size == (20.0, 5.0, 2.0) and all(isinstance(x, float) for x in s.specimen.size)
    assert s.mesh == MeshSpec(size=1.0, order=1, cell="tet")
    assert s.test == TestSpec(kind="uniaxial", grips="roller", stretch=(1.1,), steps=10)
    assert s.measure == MeasureSpec(modulus_window=(0.0005, 0.0025), gauge_length=None, fit="regression")
    assert s.solver == SolverSpec(rtol=1e-8, max_iterations=25, max_cutbacks=8)
    assert s.source == MINIMAL and s.source is not MINIMAL


def test_biaxial_alias_and_e_m_root():
    m = from_pair({"E": 10.0, "nu": -0.3})
    s = parse_scene(apply_overrides(MINIMAL, {"test.kind": "biaxial", "test.stretch": [1.2, 1.0],
                                              "test.grips": "clamped"}))
    assert s.test.stretch == (1.2, 1.0) and s.test.grips == "clamped"
    data = copy.deepcopy(MINIMAL)
    data["material"] = {"model": "stvk", "E": 10.0, "M": m.M, "root": "minus"}
    assert math.isclose(parse_scene(data).material.moduli.nu, -0.3)
    data["material"] = {"model": "stvk", "E": 10.0, "G": 4.0}
    assert parse_scene(data).material.given == {"E": 10.0, "mu": 4.0}


def _parse_error(overrides=None, drop=None):
    data = apply_overrides(MINIMAL, overrides or {})
    if drop:
        section, _, key = drop.partition(".")
        if key:
            del data[section][key]
        else:
            del data[section]
    with pytest.raises(SceneError) as exc:
        parse_scene(data, origin="scenes/x.toml")
    msg = str(exc.value)
    assert msg.startswith("scenes/x.toml: ")
    return msg


@pytest.mark.parametrize("overrides, fragments", [
    ({"material.nu": 0.5}, ["material.nu = 0.5", "-1 < nu < 0.5", "incompressible"]),
    ({"material.nu": 0.7}, ["material.nu = 0.7", "-1 < nu < 0.5"]),
    ({"material.E": 0}, ["material.E must be > 0 (got 0)"]),
    ({"material.E": -1}, ["material.E must be > 0 (got -1)"]),
    ({"material.E": "10"}, ["material.E must be a number", "'10' (string)"]),
    ({"material.E": float("nan")}, ["material.E must be a finite number"]),
    ({"material.mu": 3.0}, ["[material]", "give exactly two of E, nu, lambda, mu, K, M; got E, nu, mu"]),
    ({"material.model": "mooney"},
     ["material.model must be one of linear, stvk, stvk-volumetric, neo-hookean, spring-network, mooney-rivlin, yeoh, ogden, gent, arruda-boyce; got 'mooney'"]),
    ({"material.root": "up"}, ["material.root must be one of plus, minus"]),
    ({"material.poisson": 0.3}, ["unknown key 'poisson' in [material]"]),
    ({"test.strech": 1.5}, ["unknown key 'strech' in [test] (allowed: kind, grips, stretch, shear, twist",
                            "did you mean 'stretch'?"]),
    ({"test.stretch": -1}, ["test.stretch must be > 0 (allowed 0.2..10), got -1"]),
    ({"test.stretch": 0}, ["test.stretch must be > 0 (allowed 0.2..10), got 0"]),
    ({"test.stretch": 20}, ["test.stretch", "0.2..10", "got 20"]),
    ({"test.stretch": 1}, ["test.stretch", "no load"]),
    ({"test.stretch": [1.5]}, ["test.stretch must be a single number for kind = 'uniaxial'"]),
    ({"test.stretch": True}, ["test.stretch must be a number", "true (boolean)"]),
    ({"test.kind": "biaxial", "test.stretch": [1.2, 1.1, 1.0]}, ["test.stretch", "[sx, sy]", "biaxial"]),
    ({"test.kind": "biaxial", "test.stretch": 1.2}, ["test.stretch", "[sx, sy]"]),
    ({"test.kind": "biaxial", "test.stretch": [1.2, -1]}, ["test.stretch[1] must be > 0"]),
    ({"test.kind": "biaxial", "test.stretch": [1, 1.0]}, ["test.stretch", "no load"]),
    ({"test.kind": "shear"}, ["test.kind must be one of uniaxial, biaxial, planar, simple-shear, confined-compression, torsion, "
                                 "inflation; got 'shear'"]),
    ({"test.grips": "glued"}, ["test.grips must be one of roller, clamped"]),
    ({"test.steps": 0}, ["test.steps must be an integer 1..10000, got 0"]),
    ({"test.steps": 10001}, ["test.steps must be an integer 1..10000, got 10001"]),
    ({"test.steps": 2.5}, ["test.steps must be an integer 1..10000, got 2.5"]),
    ({"test.steps": True}, ["test.steps must be an integer", "boolean"]),
    ({"mesh.size": True}, ["mesh.size must be a number", "boolean"]),
    ({"mesh.size": 0}, ["mesh.size must be > 0 and <= 20", "got 0"]),
    ({"mesh.size": 25}, ["mesh.size must be > 0 and <= 20 (the largest specimen dimension), got 25"]),
    ({"mesh.order": 3}, ["mesh.order must be an integer 1..2, got 3"]),
    ({"mesh.cell": "prism"}, ["mesh.cell must be one of tet, hex; got 'prism'"]),
    ({"specimen.shape": "torus"}, ["specimen.shape must be one of block, dogbone"]),
    ({"specimen.size": [10, 10]}, ["specimen.size must be a list of 3 numbers"]),
    ({"specimen.size": [10, -1, 10]}, ["specimen.size[1] must be > 0, got -1"]),
    ({"specimen.size": [10, "x", 10]}, ["specimen.size[1] must be a number"]),
    ({"measure.modulus_window": [0.003, 0.001]}, ["measure.modulus_window must satisfy 0 <= a < b <= 0.05"]),
    ({"measure.modulus_window": [0.0, 0.1]}, ["measure.modulus_window[1] must be >= 0 and <= 0.05"]),
    ({"measure.modulus_window": 0.001}, ["measure.modulus_window must be a list of 2 numbers"]),
    ({"measure.gauge_length": 20}, ["measure.gauge_length must be > 0 and < 20 (the specimen length)"]),
    ({"measure.gauge_length": 0}, ["measure.gauge_length must be > 0"]),
    ({"measure.fit": "spline"}, ["measure.fit must be one of regression, chord; got 'spline'"]),
    ({"measure.modulus_points": -1}, ["measure.modulus_points must be an integer 0..100, got -1"]),
    ({"measure.modulus_points": 1.5}, ["measure.modulus_points must be an integer 0..100"]),
    ({"solver.rtol": 0.1}, ["solver.rtol must be >= 1e-14 and <= 0.01, got 0.1"]),
    ({"solver.max_iterations": 0}, ["solver.max_iterations must be an integer 1..200, got 0"]),
    ({"solver.max_cutbacks": 31}, ["solver.max_cutbacks must be an integer 0..30, got 31"]),
    ({"name": "a b"}, ["name must match [A-Za-z0-9._-]+", "'a b'"]),
    ({"name": ".."}, ["name must match"]),
    ({"description": 3}, ["description must be a string"]),
])
def test_invalid_values(overrides, fragments):
    msg = _parse_error(overrides)
    for frag in fragments:
        assert frag in msg, msg


@pytest.mark.parametrize("drop, fragment", [
    ("test.stretch", "missing required key test.stretch"),
    ("test.kind", "missing required key test.kind"),
    ("material.model", "missing required key material.model"),
    ("mesh.size", "missing required key mesh.size"),
    ("specimen.shape", "missing required key specimen.shape"),
    ("specimen.size", "missing required key specimen.size"),
    ("name", "missing required key name"),
    ("test", "missing required section [test]"),
])
def test_missing(drop, fragment):
    assert fragment in _parse_error(drop=drop)


def test_missing_moduli_names_material():
    data = copy.deepcopy(MINIMAL)
    del data["material"]["E"], data["material"]["nu"]
    with pytest.raises(SceneError, match=r"\[material\].*give exactly two"):
        parse_scene(data)


def test_unknown_section_and_top_level_key():
    data = dict(MINIMAL, solvr={"rtol": 1e-6})
    with pytest.raises(SceneError, match=r"unknown section \[solvr\].*did you mean 'solver'"):
        parse_scene(data)
    with pytest.raises(SceneError, match=r"unknown top-level key 'nmae'"):
        parse_scene(dict(MINIMAL, nmae="x"))
    with pytest.raises(SceneError, match=r"\[mesh\] must be a table"):
        parse_scene(dict(MINIMAL, mesh=2.5))


def test_toml_syntax_error(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text(EXAMPLE.replace('stretch = 1.5', 'stretch = = 1.5'), encoding="utf-8")
    with pytest.raises(SceneError) as exc:
        load_scene(path)
    assert str(path) in str(exc.value) and "TOML syntax error" in str(exc.value)
    assert "line" in str(exc.value)  # tomllib's own location message is kept


def test_load_errors_mention_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(EXAMPLE.replace("nu = 0.3", "nu = 0.5"), encoding="utf-8")
    with pytest.raises(SceneError, match=r"bad\.toml: material\.nu = 0\.5"):
        load_scene(path)
    with pytest.raises(SceneError, match="missing.toml: cannot read"):
        load_scene(tmp_path / "missing.toml")


def test_content_hash_stable_across_key_order(example_file):
    a = load_scene(example_file)
    reordered = {k: (dict(reversed(list(v.items()))) if isinstance(v, dict) else v)
                 for k, v in reversed(list(a.source.items()))}
    b = parse_scene(reordered)
    assert list(b.source) != list(a.source)
    assert a.content_hash() == b.content_hash()
    assert len(a.content_hash()) == 64
    c = parse_scene(apply_overrides(a.source, {"material.nu": 0.31}))
    assert c.content_hash() != a.content_hash()


def test_apply_overrides():
    out = apply_overrides(MINIMAL, {"material.nu": 0.45, "mesh.size": 2, "solver.rtol": 1e-6,
                                    "name": "sweep-1"})
    assert out["material"]["nu"] == 0.45 and out["mesh"]["size"] == 2
    assert out["solver"] == {"rtol": 1e-6} and out["name"] == "sweep-1"
    assert MINIMAL["material"]["nu"] == 0.25 and "solver" not in MINIMAL  # input untouched
    s = parse_scene(out)
    assert math.isclose(s.material.moduli.nu, 0.45) and s.solver.rtol == 1e-6
    with pytest.raises(SceneError, match=r"unknown section \[materal\].*did you mean 'material'"):
        apply_overrides(MINIMAL, {"materal.nu": 0.4})
    with pytest.raises(SceneError, match="override 'material'"):
        apply_overrides(MINIMAL, {"material": 0.4})
    with pytest.raises(SceneError, match="override 'a.b.c'"):
        apply_overrides(MINIMAL, {"a.b.c": 1})
    with pytest.raises(SceneError, match=r"unknown key 'nuu' in \[material\]"):
        parse_scene(apply_overrides(MINIMAL, {"material.nuu": 0.4}))


def test_modulus_points_reach_the_schedule():
    from vlab.loading.schedule import monotonic_schedule
    from vlab.scene import load_scene

    from pathlib import Path

    scene = load_scene(Path(__file__).resolve().parents[1] / "benchmarks" / "block16.toml")
    assert scene.measure.modulus_points == 0
    levels = monotonic_schedule(scene.test.stretch, scene.test.steps, scene.measure.modulus_window,
                                scene.measure.modulus_points)
    assert len(levels) == scene.test.steps


@pytest.mark.parametrize("name, names", [
    ("dogbone-iso527-2-1a", "specimen.gauge_length"), ("mesh-import-bar", "specimen.gauge_marks"),
    ("shear-plates-neo-hookean", "the layer's shear"), ("double-lap-neo-hookean", "the layer's shear"),
    ("sphere-inflation", "the shell's hoop"), ("membrane-bulge", "the pole"),
])
def test_measure_gauge_length_is_refused_where_the_shape_is_built_without_it(name, names):
    """A shape whose build ignores measure.gauge_length (a standard dumb-bell's marks, a file's
    gauge_marks, no extensometer) refuses the key naming where its gauge comes from, instead of
    measuring over another length than the scene says."""
    import tomllib

    folder = Path(__file__).resolve().parents[1] / "specimens"
    raw = tomllib.loads((folder / f"{name}.toml").read_text(encoding="utf-8"))
    raw.setdefault("measure", {})["gauge_length"] = 4.0
    with pytest.raises(SceneError, match=rf"measure.gauge_length does not apply to specimen.shape = .*{names}"):
        parse_scene(raw, base_dir=folder)


@pytest.mark.parametrize("name", ["block-neo-hookean", "sheet-strip-clamped", "planar-tension-neo-hookean",
                                  "cylinder-torsion", "cruciform-slotted"])
def test_measure_gauge_length_moves_the_marks_where_the_shape_takes_it(name):
    import tomllib

    import numpy as np

    from vlab.geometry.shapes import SHAPES, build_specimen

    folder = Path(__file__).resolve().parents[1] / "specimens"
    raw = tomllib.loads((folder / f"{name}.toml").read_text(encoding="utf-8"))
    raw.setdefault("measure", {})["gauge_length"] = 4.0
    scene = parse_scene(raw, base_dir=folder)
    assert SHAPES[scene.specimen.shape].gauge_from is None
    marks = build_specimen(scene.specimen, scene.mesh, scene.measure.gauge_length).extensometers[0]
    assert np.linalg.norm(np.subtract(marks.b, marks.a)) == pytest.approx(4.0, rel=1e-12)
