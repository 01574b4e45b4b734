"""Cruciform specimens: outline and mesh, errors naming the field, the equibiaxial symmetry of the
two axes, the centre-vs-nominal stress correction factor, and E, ν recovered from biaxial tests."""

import json
import math

import numpy as np
import pytest
import skfem

from vlab.geometry.cruciform import CruciformDimensions, cruciform_specimen
from vlab.geometry.quality import mesh_quality
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene

PLAIN = {"arm_width": 20.0, "arm_length": 30.0, "gauge_region": 10.0, "fillet_radius": 5.0,
         "thickness": 2.0, "grip_length": 10.0}
SLOTTED = PLAIN | {"slit_count": 3, "slit_width": 1.0, "slit_length": 20.0}


def scene(specimen=PLAIN, stretch=(1.0002, 1.0002), model="linear", mesh=None, **measure):
    return parse_scene({
        "name": "c",
        "specimen": {"shape": "cruciform"} | specimen,
        "mesh": {"size": 2.5, "cell": "hex"} | (mesh or {}),
        "material": {"model": model, "E": 10.0, "nu": 0.3},
        "test": {"kind": "biaxial", "stretch": list(stretch), "steps": 1},
        "measure": {"modulus_window": [1e-5, 5e-5]} | measure,
    })


def volume(mesh) -> float:
    element = skfem.ElementHex1() if isinstance(mesh, skfem.MeshHex) else skfem.ElementTetP1()
    return skfem.Functional(lambda w: 1.0).assemble(skfem.Basis(mesh, element))


@pytest.mark.parametrize("cell", ["hex", "tet"])
@pytest.mark.parametrize("dims", [PLAIN, SLOTTED], ids=["plain", "slotted"])
def test_mesh_volume_matches_the_outline(dims, cell):
    d = CruciformDimensions(**dims)
    mesh = cruciform_specimen(d, 2.5, cell).mesh
    w, ell, r, h = d.arm_width, d.arm_length, d.fillet_radius, d.thickness
    area = w * w + 4 * w * ell + 4 * (r * r - math.pi * r * r / 4)
    area -= 4 * d.slit_count * d.slit_width * d.slit_length
    assert volume(mesh) == pytest.approx(area * h, rel=2e-3)  # chords of the fillet arcs
    assert mesh_quality(mesh).min_quality > 0.15


@pytest.mark.parametrize("cell", ["hex", "tet"])
def test_mesh_is_symmetric_under_the_x_y_swap_and_the_mirrors(cell):
    mesh = cruciform_specimen(CruciformDimensions(**SLOTTED), 2.5, cell).mesh
    key = lambda P: set(map(tuple, np.round(P.T, 9)))  # noqa: E731
    nodes = key(mesh.p)
    assert key(mesh.p[[1, 0, 2]]) == nodes
    assert key(mesh.p * np.array([[-1], [1], [1]])) == nodes
    cells = {frozenset(map(tuple, np.round(mesh.p[:, t].T, 9))) for t in mesh.t.T}
    swapped = {frozenset(map(tuple, np.round(mesh.p[[1, 0, 2]][:, t].T, 9))) for t in mesh.t.T}
    assert cells == swapped  # the elements themselves, not just the nodes (tet split included)


def test_slits_cut_the_arms_into_fingers_held_by_the_grips():
    spec = cruciform_specimen(CruciformDimensions(**SLOTTED), 2.5, "hex")
    X = spec.mesh.p.T
    centroids = spec.mesh.p[:, spec.mesh.t].mean(axis=1).T
    in_slit = (centroids[:, 0] > 20.0) & (np.abs(centroids[:, 1]) < 0.5)  # the middle slit of +x
    assert not in_slit.any()
    grip = next(g for g in spec.grips if g.name == "x+").select(X)
    assert np.all(X[grip, 0] >= 30.0 - 1e-9) and grip.sum() > 0
    assert spec.grip_separation == {0: 60.0, 1: 60.0} and spec.area0 == {0: 40.0, 1: 40.0}


@pytest.mark.parametrize("change, fragment", [
    ({"fillet_radius": 25.0}, "specimen.fillet_radius = 25 mm is too large for the arms: it must be in [0, "
                              "arm_length - grip_length = 20] mm"),
    ({"gauge_region": 25.0}, "specimen.gauge_region must be in (0, arm_width = 20] mm"),
    ({"thickness": -2.0}, "specimen.thickness must be > 0"),
    ({"grip_length": 30.0}, "specimen.grip_length must be in (0, arm_length = 30) mm"),
    ({"slit_count": 3, "slit_width": 1.0, "slit_length": 28.0},
     "specimen.slit_length must be in (grip_length = 10, arm_length - fillet_radius = 25] mm"),
    ({"slit_count": 4, "slit_width": 6.0, "slit_length": 20.0}, "specimen.slit_width must be in (0, "
                                                                 "arm_width / slit_count = 5) mm"),
    ({"slit_width": 1.0}, "specimen.slit_width needs specimen.slit_count >= 1"),
    ({"arm_radius": 1.0}, "unknown key 'arm_radius' in [specimen]"),
    ({"gauge_thickness": 2.5, "thinning_length": 2.0}, "specimen.gauge_thickness must be in (0, thickness = 2) mm"),
    ({"gauge_thickness": 1.0, "thinning_length": 6.0}, "specimen.thinning_length must be in (0, (arm_width - "
                                                        "gauge_region)/2 = 5] mm"),
    ({"thinning_length": 2.0}, "specimen.thinning_length needs specimen.gauge_thickness"),
])
def test_bad_geometry_is_a_scene_error_naming_the_field_and_range(change, fragment):
    with pytest.raises(SceneError) as info:
        scene(PLAIN | change)
    assert fragment in str(info.value)


def test_cruciform_tests_are_biaxial_between_clamped_grips():
    raw = {"name": "c", "specimen": {"shape": "cruciform"} | PLAIN, "mesh": {"size": 2.5},
           "material": {"model": "linear", "E": 10.0, "nu": 0.3},
           "test": {"kind": "uniaxial", "stretch": 1.01}}
    with pytest.raises(SceneError, match="test.kind must be one of biaxial"):
        parse_scene(raw)
    with pytest.raises(SceneError, match=r"measure.gauge_length must be in \(0, specimen.gauge_region = 10\]"):
        scene(gauge_length=12.0)


@pytest.fixture(scope="module")
def runs():
    cache = {}

    def get(**kw):
        key = json.dumps(kw, sort_keys=True)
        if key not in cache:
            cache[key] = run_scene(scene(**kw))
        return cache[key]
    return get


@pytest.mark.parametrize("cell", ["hex", "tet"])
def test_equibiaxial_axes_agree_to_1e_6(cell, runs):
    result = runs(mesh={"cell": cell}, specimen=SLOTTED)
    c = result.curve
    for a, b in ((c.force[0], c.force[1]), (c.strain[0], c.strain[1]),
                 (c.centre["stress_x"], c.centre["stress_y"])):
        assert np.allclose(a, b, rtol=1e-6, atol=0) and abs(a[-1]) > 0


@pytest.mark.parametrize("specimen", [PLAIN, SLOTTED], ids=["plain", "slotted"])
def test_centre_stress_is_below_nominal_with_its_correction_factor_reported(specimen, runs, tmp_path):
    from vlab.report.html import cruciform_rows
    from vlab.report.results import result_to_dict

    data = json.loads(json.dumps(result_to_dict(runs(specimen=specimen))))
    row = data["cruciform"]["small_strain"]
    for xy in "xy":
        k = row[f"correction_factor_{xy}"]
        assert k == pytest.approx(row[f"centre_stress_{xy}"] / row[f"nominal_stress_{xy}"])
        assert 0.5 < k < 1.0
    assert len(data["curve"]["centre_stress_x"]) == len(data["curve"]["force"])
    assert any(f"correction factor {k:.4g}" in text for _, text in cruciform_rows(data["cruciform"])
               for k in [row["correction_factor_x"]])


def test_report_page_shows_nominal_and_centre_stress(runs, tmp_path):
    from vlab.report.writer import ReportOptions, write_run

    write_run(runs(specimen=SLOTTED), tmp_path / "out", options=ReportOptions(render=False, vtu=False))
    page = (tmp_path / "out" / "index.html").read_text()
    assert "correction factor" in page and "stress nominal / centre" in page


def test_thinned_centre_has_the_gauge_thickness_and_stays_symmetric(runs):
    spec = cruciform_specimen(CruciformDimensions(**THINNED), 2.5, "hex")
    p = spec.mesh.p
    centre = (np.abs(p[0]) < 5.0 + 1e-9) & (np.abs(p[1]) < 5.0 + 1e-9)
    assert p[2, centre].min() == pytest.approx(0.5) and p[2, centre].max() == pytest.approx(1.5)
    assert p[2].min() == pytest.approx(0.0) and p[2].max() == pytest.approx(2.0)
    assert spec.area0[0] == pytest.approx(20.0)  # arm width x gauge thickness
    assert spec.thickness.length == pytest.approx(1.0)
    c = runs(specimen=THINNED).curve
    assert np.allclose(c.force[0], c.force[1], rtol=1e-6, atol=0)


def test_slits_bring_the_correction_factor_towards_one(runs):
    plain = runs(specimen=PLAIN).diagnostics.cruciform["small_strain"]["correction_factor_x"]
    slotted = runs(specimen=SLOTTED).diagnostics.cruciform["small_strain"]["correction_factor_x"]
    assert plain < slotted < 1.0


TOLERANCE = 1e-3  # recovered E and nu at 2e-4 strain vs the input (measured: 1e-7 linear, 1.3e-4 Neo-Hookean)
THINNED = PLAIN | {"gauge_thickness": 1.0, "thinning_length": 3.0}


@pytest.mark.parametrize("stretch, model, specimen", [
    ((1.0002, 1.0002), "linear", PLAIN), ((1.0002, 1.0001), "linear", PLAIN), ((1.0001, 1.0002), "linear", PLAIN),
    ((1.0002, 1.0), "linear", PLAIN), ((1.0002, 1.0002), "neo-hookean", PLAIN),
    ((1.0002, 1.0001), "neo-hookean", PLAIN), ((1.0002, 1.0002), "linear", THINNED),
    ((1.0002, 1.0001), "neo-hookean", SLOTTED),
], ids=["equibiaxial-linear", "2-1-linear", "1-2-linear", "constrained-y-linear", "equibiaxial-nh", "2-1-nh",
        "thinned-equibiaxial-linear", "slotted-2-1-nh"])
def test_E_and_nu_are_recovered_from_the_centre_state(stretch, model, specimen, runs):
    result = runs(stretch=stretch, model=model, specimen=specimen)
    assert result.converged
    assert result.constants.E == pytest.approx(10.0, rel=TOLERANCE)
    assert result.constants.nu == pytest.approx(0.3, rel=TOLERANCE)
    # the lab's nominal-stress figure is off by about 1/k: visibly not E
    if stretch[0] == stretch[1]:
        assert result.diagnostics.cruciform["E_nominal"] > 1.2 * result.constants.E
