"""Alignment as an uncertainty source (issue 35): a misaligned moving grip (test.misalignment),
the ASTM E1012 percent bending of virtual strain gauges on the faces, and [uncertainty] alignment.

Beam theory of the block (length L = 40 between the clamps, thickness h = 2, width 10 mm, linear
elastic, both grips clamped, grip travel Δ = (λ − 1) L): the moving clamp offset by e along z and
turned by θ about y is a clamped–clamped beam with w(0) = w'(0) = 0, w(L) = e, w'(L) = θ:

    w(ξ) = e (3ξ² − 2ξ³) + θ L (ξ³ − ξ²),   κ(ξ) = w'' = e (6 − 12ξ)/L² + θ (6ξ − 2)/L   (ξ = x/L)

A face fibre at z − z_c = ±h/2 strains ε = ε_a ∓ (h/2) κ with ε_a = Δ/L, so two opposite gauges read

    B = (ε_top − ε_bottom)/(ε_top + ε_bottom) × 100 = −(h/2) κ(ξ) L/Δ × 100

At the gauge centre (ξ = 1/2) only the tilt bends: B = −θ h/(2Δ) × 100 (−1.454 % at θ = 0.1°);
at the planes ξ = 1/2 ∓ 0.2 the tilt gives −(h/2)θ(1 ∓ 1.2)/Δ and the offset ∓1.2 e h/(L Δ) × 100.
The tolerance: 3 % of B at the centre plus 0.05 percentage points (shear deformation of a beam of
L/h = 20 and the clamps' restraint of the Poisson contraction; measured 0.5 %).

In the width plane (offset e_y along y, tilt θ_z about z: the bar bends about its stiff axis,
h → the width b = 10 mm, L/b = 4) shear deformation matters, so the reference is the Timoshenko
beam: the clamped–clamped element's end moments (Przemieniecki, Theory of Matrix Structural
Analysis, 1968, the shear-deformable beam element) for w(L) = e, ψ(L) = θ,

    M₁ = EI (−6 L e + (2 − φ) L² θ) / (L³ (1 + φ)),   M₂ = EI (−6 L e + (4 + φ) L² θ) / (L³ (1 + φ)),
    φ = 12 EI/(κ G A L²) = 2 (1 + ν) b²/(κ L²)   (κ = 5/6),

a moment linear in between, κ(ξ) = −M₁(1 − ξ)/EI + M₂ ξ/EI (φ = 0: the beam above), and the same
B(ξ) with b for h. At the centre the tilt's B = −θ b/(2Δ) × 100 does not depend on φ.

The extensometer sits on the top face over the centre ±G/2, where the tilt's bending is linear in
x, so it reads ε_a (1 + B_c/100) and the lab's E = E₀ /(1 + B_c/100): E's bias grows with the tilt.
"""

import math
import re
from types import SimpleNamespace

import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.fields import SceneError
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import parse_scene
from vlab.study.summary import RunKnobs, summarize
from vlab.uncertainty.budget import compute_budget
from vlab.uncertainty.spec import parse_uncertainty

L, H = 40.0, 2.0
STRETCH = 1.003


def _source(misalignment=None, grips="clamped", uncertainty=None):
    test = {"kind": "uniaxial", "grips": grips, "stretch": STRETCH, "steps": 3}
    if misalignment is not None:
        test["misalignment"] = misalignment
    src = {"name": "bar", "specimen": {"shape": "block", "size": [L, 10.0, H]}, "mesh": {"size": 1.0, "cell": "hex"},
           "material": {"model": "linear", "E": 1000.0, "nu": 0.3}, "test": test}
    return src | ({"uncertainty": uncertainty} if uncertainty is not None else {})


def _run(offset=0.0, tilt=0.0) -> dict:
    return result_to_dict(run_scene(parse_scene(_source({"offset": offset, "tilt": tilt}))))


def _beam(xi: float, offset: float, tilt: float) -> float:
    """Percent bending of the clamped–clamped beam at ξ (module docstring)."""
    delta = (STRETCH - 1.0) * L
    kappa = offset * (6 - 12 * xi) / L**2 + math.radians(tilt) * (6 * xi - 2) / L
    return -(H / 2) * kappa * L / delta * 100.0


@pytest.mark.parametrize("offset, tilt", [(0.0, 0.1), (0.05, 0.0), (0.05, 0.2)])
def test_percent_bending_of_the_face_gauges_matches_the_clamped_beam(offset, tilt):
    b = _run(offset, tilt)["bending"]["small_strain"]
    for plane, xi in zip(b["planes"], (0.3, 0.5, 0.7)):
        assert plane["x"] == pytest.approx(xi * L)
        expect = _beam(xi, offset, tilt)
        assert plane["percent_bending_thickness"] == pytest.approx(expect, rel=0.03, abs=0.05), (xi, expect)
        # four gauges: a is the mean of all four (the width faces read the axis's strain within 0.3 %)
        assert plane["percent_bending"] == pytest.approx(abs(plane["percent_bending_thickness"]), rel=0.01, abs=1e-9)
        assert plane["percent_bending_width"] == pytest.approx(0.0, abs=1e-6)
    assert b["percent_bending"] == b["planes"][1]["percent_bending"]


WIDTH = 10.0


def _timoshenko(xi: float, offset: float, tilt: float, b: float = WIDTH, nu: float = 0.3) -> float:
    """Percent bending of the shear-deformable clamped–clamped beam at ξ (module docstring)."""
    phi = 2 * (1 + nu) * b**2 / (5 / 6 * L**2)
    theta = math.radians(tilt)
    m1 = (-6 * L * offset + (2 - phi) * L**2 * theta) / (L**3 * (1 + phi))
    m2 = (-6 * L * offset + (4 + phi) * L**2 * theta) / (L**3 * (1 + phi))
    kappa = -m1 * (1 - xi) + m2 * xi
    return -(b / 2) * kappa / (STRETCH - 1.0) * 100.0


@pytest.mark.parametrize("offset_y, tilt_z", [(0.0, 0.1), (0.05, 0.0), (0.05, 0.2)])
def test_in_the_width_plane_the_width_face_gauges_match_the_timoshenko_beam(offset_y, tilt_z):
    """B_y at the three planes within 3 % plus 0.15 points (the clamps' restraint of the
    contraction over a width of 10 mm, 12 mm from the planes ξ = 0.3 and 0.7; measured: the centre
    within 0.4 %, the outer planes within 1.5 %), the thickness pair unbent, and the four-gauge B
    the width pair's |B_y|."""
    b = result_to_dict(run_scene(parse_scene(_source({"offset": [offset_y, 0.0], "tilt": [0.0, tilt_z]}))))
    small = b["bending"]["small_strain"]
    for plane, xi in zip(small["planes"], (0.3, 0.5, 0.7)):
        expect = _timoshenko(xi, offset_y, tilt_z)
        assert plane["percent_bending_width"] == pytest.approx(expect, rel=0.03, abs=0.15), (xi, expect)
        assert plane["percent_bending_thickness"] == pytest.approx(0.0, abs=1e-6)
        assert plane["percent_bending"] == pytest.approx(abs(plane["percent_bending_width"]), rel=0.01, abs=1e-6)
    # the top-face extensometer lies on the width plane's neutral axis: E is not biased
    assert b["measured"]["E"] == pytest.approx(_run()["measured"]["E"], rel=5e-4)


def test_both_planes_combine_in_the_four_gauge_percent_bending():
    """offset and tilt in both planes at once: each pair reads its own plane (the superposition of
    the two single-plane runs, linear elasticity), and B = √(B_y² + B_z²) with the axial strain
    the four gauges' mean."""
    both = _source({"offset": [0.05, 0.05], "tilt": [0.1, 0.1]})
    planes = result_to_dict(run_scene(parse_scene(both)))["bending"]["small_strain"]["planes"]
    thick = _run(0.05, 0.1)["bending"]["small_strain"]["planes"]
    for p, t, xi in zip(planes, thick, (0.3, 0.5, 0.7)):
        assert p["percent_bending_thickness"] == pytest.approx(t["percent_bending_thickness"], rel=0.01, abs=0.01)
        assert p["percent_bending_width"] == pytest.approx(_timoshenko(xi, 0.05, 0.1), rel=0.03, abs=0.15)
        assert p["percent_bending"] == pytest.approx(math.hypot(p["percent_bending_width"],
                                                                p["percent_bending_thickness"]), rel=0.01)


def test_the_four_gauge_formula_reproduces_the_mts_alignment_manual_s_example():
    """MTS 709 Alignment System manual (p. 70, "ASTM E1012 true max", four sensors): readings
    2100, 2100, 1900, 1900 µε around the section give a = 2000, B = ½√((b₁ − b₃)² + (b₂ − b₄)²) =
    141 µε, 7.07 % of a; the rectangle's corner fibre sees 200 µε, 10 %."""
    from vlab.measure.bending import four_gauge_bending

    B, corner = four_gauge_bending(2100e-6, 1900e-6, 2100e-6, 1900e-6)  # top, bottom, y1, y0
    assert B == pytest.approx(100 * math.sqrt(2) * 100 / 2000) and corner == pytest.approx(10.0)


def test_an_aligned_clamped_bar_has_no_bending_and_the_bias_of_E_grows_with_the_tilt():
    E0 = _run()["measured"]["E"]
    assert _run()["bending"]["small_strain"]["max_percent_bending"] == pytest.approx(0.0, abs=1e-6)
    biases = []
    for tilt in (0.1, 0.2, 0.4):
        r = _run(tilt=tilt)
        B = r["bending"]["small_strain"]["percent_bending_thickness"]
        bias = r["measured"]["E"] / E0 - 1.0
        assert bias == pytest.approx(1.0 / (1.0 + B / 100.0) - 1.0, rel=0.02)  # the top-face extensometer
        biases.append(bias)
    assert 0 < biases[0] < biases[1] < biases[2]
    assert biases[2] == pytest.approx(4 * biases[0], rel=0.1)  # linear in θ at small tilt (+1.5 % per 0.1°)


def test_without_misalignment_results_carry_no_bending():
    r = result_to_dict(run_scene(parse_scene(_source())))
    assert r["bending"] is None


def _in_process(points, what):
    s = [summarize(p.source, RunKnobs(), p.label, p.base_dir) | {"cache_hit": False} for p in points]
    return SimpleNamespace(summaries=s, cache_hits=0, computed=len(s), seconds={})


def test_the_budget_draws_the_tilt_and_its_gum_sensitivity_is_the_beam_s():
    src = _source(uncertainty={"samples": 4, "alignment": {"tilt": 0.1}, "load_cell_class": "none",
                               "extensometer_class": "none", "resolution": False})
    scene = parse_scene(src)
    spec = parse_uncertainty(src["uncertainty"], scene)
    budget, runs = compute_budget(src, spec, ".", _in_process, scene.measure.modulus_window[0])
    (row,) = [r for r in budget["E"]["contributions"] if r["input"] == "grip tilt (about y, thickness plane)"]
    E0 = budget["E"]["nominal"]
    # dE/dθ = E0 h/(2Δ) per radian at θ = 0 (E = E0/(1 + B/100), B = −θh/(2Δ) × 100)
    assert row["sensitivity"] == pytest.approx(E0 * H / (2 * (STRETCH - 1) * L) * math.pi / 180, rel=0.03)
    assert row["share"] == pytest.approx(1.0)
    pb = budget["percent_bending"]
    assert pb["nominal"] == pytest.approx(0.0, abs=1e-6) and pb["max_abs"] > 0


def test_a_budget_in_both_planes_ranks_the_thickness_tilt_and_reports_each_plane_s_bending():
    """The extensometer on the top face sees the thickness plane's tilt (share ≈ 1) and not the
    width plane's (it lies on that plane's neutral axis); budget.json → percent_bending has both
    planes' signed bending and the four-gauge B of every sample."""
    src = _source(uncertainty={"samples": 4, "alignment": {"tilt": [0.1, 0.1]}, "load_cell_class": "none",
                               "extensometer_class": "none", "resolution": False})
    scene = parse_scene(src)
    spec = parse_uncertainty(src["uncertainty"], scene)
    budget, runs = compute_budget(src, spec, ".", _in_process, scene.measure.modulus_window[0])
    shares = {r["input"]: r["share"] for r in budget["E"]["contributions"]}
    assert shares["grip tilt (about y, thickness plane)"] > 0.999
    assert shares["grip tilt (about z, width plane)"] < 1e-3
    pb = budget["percent_bending"]
    for s in runs.summaries:
        m = s["measured"]
        assert m["percent_bending"] == pytest.approx(math.hypot(m["percent_bending_thickness"],
                                                                m["percent_bending_width"]), rel=0.01)
    assert pb["width_plane"]["max_abs"] > 0 and pb["thickness_plane"]["max_abs"] > 0
    assert pb["max_abs"] == max(s["measured"]["percent_bending"] for s in runs.summaries)


def test_a_sample_s_misalignment_is_the_scene_s_plus_its_draws_in_each_plane():
    """A scene misaligned in the thickness plane (the scalar form: tilt θ_y, offset e_z) budgeted in
    both planes: each drawn deviation lands on its own component, the slip on test.grip_slip."""
    from vlab.uncertainty.model import scene_source

    src = _source({"tilt": 0.2, "offset": 0.03},
                  uncertainty={"alignment": {"offset": [0.01, 0.02], "tilt": [0.1, 0.3]}, "grip_slip": 1e-4})
    spec = parse_uncertainty(src["uncertainty"], parse_scene(src))
    d = {"grip offset (width y)": 0.5, "grip offset (thickness z)": 0.25, "grip tilt (about y, thickness plane)": 1.0,
         "grip tilt (about z, width plane)": -2.0, "grip slip": -2e-5}
    test = scene_source(src, spec, d)["test"]
    assert test["misalignment"] == {"offset": [0.5, 0.28], "tilt": [1.2, -2.0]}
    assert test["grip_slip"] == pytest.approx(3e-5)
    assert parse_scene(scene_source(src, spec, d)).test.misalignment == (0.5, 0.28, 1.2, -2.0)


@pytest.mark.parametrize("table, needle", [
    ({"alignment": {"tilt": -0.1}}, "uncertainty.alignment.tilt must be >= 0"),
    ({"alignment": {"offset": -1}}, "uncertainty.alignment.offset must be >= 0"),
    ({"alignment": {"tilt": 20}}, "uncertainty.alignment.tilt must be >= 0 and <= 10"),
    ({"alignment": {"twist": 1}}, "twist"),
    ({"alignment": {"tilt": [0.1, 11]}}, "uncertainty.alignment.tilt[1] must be >= 0 and <= 10"),
    ({"alignment": {"offset": [0.1, -0.1]}}, "uncertainty.alignment.offset[1] must be >= 0"),
])
def test_bad_alignment_entries_are_refused_naming_the_field(table, needle):
    with pytest.raises(SceneError, match=re.escape(needle)):
        parse_scene(_source(uncertainty=table))


@pytest.mark.parametrize("misalignment, grips, needle", [
    ({"tilt": 90}, "clamped", "test.misalignment.tilt must be > -90 and < 90"),
    ({"tilt": -95}, "clamped", "test.misalignment.tilt must be > -90 and < 90"),
    ({"offset": "1"}, "clamped", "test.misalignment.offset must be a number"),
    ({"tilt": 1}, "roller", "test.misalignment applies to a uniaxial test in clamped grips"),
    ({"tilt": [0.1, 95]}, "clamped", "test.misalignment.tilt[1] must be > -90 and < 90"),
    ({"offset": [0.1]}, "clamped", "test.misalignment.offset must be a list of 2 numbers [e_y, e_z]"),
])
def test_bad_misalignment_is_refused_naming_the_field(misalignment, grips, needle):
    with pytest.raises(SceneError, match=re.escape(needle)):
        parse_scene(_source(misalignment, grips))


def test_the_cli_exits_2_naming_the_field(tmp_path):
    scene = tmp_path / "bar.toml"
    body = ('name = "bar"\n[specimen]\nshape = "block"\nsize = [40.0, 10.0, 2.0]\n[mesh]\nsize = 2.0\n'
            '[material]\nmodel = "linear"\nE = 1000.0\nnu = 0.3\n[test]\nkind = "uniaxial"\ngrips = "clamped"\n'
            'stretch = 1.003\n')
    scene.write_text(body + "misalignment = { tilt = 90 }\n")
    res = CliRunner().invoke(app, ["run", str(scene), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2 and "test.misalignment.tilt" in res.output and "Traceback" not in res.output
    assert not (tmp_path / "out").exists()
    scene.write_text(body + "[uncertainty]\nalignment = { offset = -0.1 }\n")
    res = CliRunner().invoke(app, ["budget", str(scene), "--out", str(tmp_path / "b")])
    assert res.exit_code == 2 and "uncertainty.alignment.offset" in res.output and "Traceback" not in res.output
    assert not (tmp_path / "b").exists()
