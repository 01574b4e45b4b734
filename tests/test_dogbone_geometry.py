"""Dogbone outlines, meshes, grips and the shipped standards' dimensions."""

import math

import numpy as np
import pytest
import skfem

from vlab.geometry.dogbone import DogboneDimensions, GeometryError, dogbone_mesh, dogbone_specimen
from vlab.geometry.quality import mesh_quality
from vlab.geometry.standards import standard_dimensions, standard_names

STANDARDS = ("ISO 527-2 1A", "ISO 527-2 1BA", "ASTM D638 IV", "ISO 37 2", "ASTM D412 C")


def dims_of(name: str, **changes) -> DogboneDimensions:
    data = standard_dimensions(name)
    standard = data.pop("standard")
    return DogboneDimensions(**(data | changes), standard=standard)


def test_every_issue_standard_is_shipped_as_package_data():
    assert set(STANDARDS) <= set(standard_names())
    assert standard_dimensions("iso 527-2 1a")["standard"] == "ISO 527-2 1A"  # case/space-insensitive
    assert standard_dimensions("no such standard") is None


@pytest.mark.parametrize("name", STANDARDS)
def test_standard_dimensions_are_consistent(name):
    dims_of(name).check()


@pytest.mark.parametrize("name, l2", [("ISO 527-2 1A", 109.3), ("ISO 527-2 1BA", 58.0)])
def test_single_arc_transition_reproduces_the_standards_distance_between_broad_portions(name, l2):
    d = dims_of(name)
    assert d.parallel_length + 2 * d.transition_length == pytest.approx(l2, abs=0.05)


@pytest.mark.parametrize("name", STANDARDS)
def test_outline_is_continuous_tangent_and_monotone(name):
    d = dims_of(name)
    L, half = d.overall_length, d.parallel_length / 2
    x = np.linspace(L / 2, L, 20001)
    y = d.half_width(x)
    assert y[0] == pytest.approx(d.width / 2) and y[-1] == pytest.approx(d.end_width / 2)
    assert np.all(np.diff(y) >= -1e-12)
    assert np.max(np.abs(np.diff(y))) < 1e-2  # no jump anywhere, junctions included
    slope = np.diff(y) / np.diff(x)
    start = np.searchsorted(x, L / 2 + half)
    assert abs(slope[start]) < 2e-2  # the fillet leaves the parallel section tangentially
    if d.outer_radius:
        j = np.searchsorted(x, L / 2 + half + d.arc_junction)
        assert abs(slope[j + 1] - slope[j - 2]) < 1e-2  # the two arcs meet tangentially


@pytest.mark.parametrize("cell", ["hex", "tet"])
@pytest.mark.parametrize("name", STANDARDS)
def test_mesh_volume_matches_the_outline_area_times_thickness(name, cell):
    d = dims_of(name)
    mesh = dogbone_mesh(d, d.width / 4, cell)
    x = np.linspace(0, d.overall_length, 200001)
    area = np.trapezoid(2 * d.half_width(x), x)
    volume = skfem.Functional(lambda w: 1.0).assemble(skfem.Basis(mesh, skfem.ElementTetP1() if cell == "tet"
                                                                  else skfem.ElementHex1()))
    assert volume == pytest.approx(area * d.thickness, rel=2e-3)  # chords of the arcs


def test_parallel_section_is_meshed_with_undistorted_boxes():
    d = dims_of("ISO 527-2 1A")
    mesh = dogbone_mesh(d, 2.5, "hex")
    c = mesh.p[:, mesh.t].mean(axis=1)
    inside = np.abs(c[0] - d.overall_length / 2) < d.parallel_length / 2
    sub = skfem.MeshHex(mesh.p, mesh.t[:, inside])
    assert mesh_quality(sub).min_quality == pytest.approx(1.0, abs=1e-12)


def test_grips_hold_the_tabs_and_gauge_marks_sit_in_the_parallel_section():
    d = dims_of("ISO 527-2 1A")
    spec = dogbone_specimen(d, 2.5, "hex")
    X = spec.mesh.p.T
    fixed, moving = spec.grips_on(0)
    assert np.all(X[fixed.select(X), 0] <= 27.5 + 1e-9) and np.any(np.isclose(X[fixed.select(X), 0], 27.5))
    assert np.all(X[moving.select(X), 0] >= 170 - 27.5 - 1e-9)
    assert spec.grip_separation[0] == pytest.approx(115.0)
    marks = spec.extensometers[0]
    assert marks.length == pytest.approx(75.0) and (marks.a[0] + marks.b[0]) / 2 == pytest.approx(85.0)
    assert spec.transverse[0].length == pytest.approx(10.0)
    assert spec.area0[0] == pytest.approx(40.0)


def test_grip_edge_within_a_fifth_of_an_element_of_the_tab_end_snaps_to_it():
    d = dims_of("ISO 37 2")  # grip_length 12.5, tab end at 12.5025
    spec = dogbone_specimen(d, 1.0, "hex")
    sizes = np.diff(np.unique(spec.mesh.p[0]))
    assert sizes.min() > 0.2
    assert spec.grip_separation[0] == pytest.approx(d.parallel_length + 2 * d.transition_length)


def test_gauge_refinement_only_refines_the_gauge_side():
    d = dims_of("ISO 527-2 1A")
    coarse, refined = dogbone_mesh(d, 5.0, "hex"), dogbone_mesh(d, 5.0, "hex", gauge_size=2.5)
    xs = np.unique(refined.p[0])
    assert np.diff(xs[xs < 27.5]).max() == pytest.approx(27.5 / 6)
    assert np.diff(xs[np.abs(xs - 85) < 40]).max() <= 2.5 + 1e-9
    assert refined.nelements > coarse.nelements


@pytest.mark.parametrize("changes, field", [
    ({"fillet_radius": 250.0}, "fillet_radius"),   # transition longer than the specimen allows
    ({"fillet_radius": 4.0}, "fillet_radius"),     # one arc cannot climb 5 mm with r = 4
    ({"gauge_length": 90.0}, "gauge_length"),
    ({"thickness": -1.0}, "thickness"),
    ({"end_width": 8.0}, "end_width"),
    ({"grip_length": 50.0}, "grip_length"),
    ({"parallel_length": 180.0}, "parallel_length"),
])
def test_impossible_dimensions_name_the_field(changes, field):
    with pytest.raises(GeometryError) as info:
        dims_of("ISO 527-2 1A", **changes).check()
    assert info.value.field == field and str(info.value).startswith(field)


def test_mesh_quality_of_ideal_and_distorted_elements():
    box = skfem.MeshHex.init_tensor(np.linspace(0, 4, 3), np.linspace(0, 1, 2), np.linspace(0, 1, 2))
    q = mesh_quality(box)
    assert q.min_quality == pytest.approx(1.0) and q.max_aspect_ratio == pytest.approx(2.0)
    p = box.p.copy()
    p[0] += 0.5 * p[1]  # shear by 45°/2: scaled Jacobian cos(atan 0.5)
    assert mesh_quality(skfem.MeshHex(p, box.t)).min_quality == pytest.approx(math.cos(math.atan(0.5)))
    regular = np.array([[0, 0, 0], [1, 0, 0], [0.5, math.sqrt(3) / 2, 0],
                        [0.5, math.sqrt(3) / 6, math.sqrt(2 / 3)]]).T
    assert mesh_quality(skfem.MeshTet(regular, np.array([[0, 1, 2, 3]]).T)).min_quality == pytest.approx(1.0)
    flat = regular.copy()
    flat[2, 3] = 1e-3
    assert mesh_quality(skfem.MeshTet(flat, np.array([[0, 1, 2, 3]]).T)).min_quality < 0.05
