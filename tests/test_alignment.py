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

The extensometer sits on the top face over the centre ±G/2, where the tilt's bending is linear in
x, so it reads ε_a (1 + B_c/100) and the lab's E = E₀ /(1 + B_c/100): E's bias grows with the tilt.
"""

import math
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


@pytest.mark.parametrize("table, needle", [
    ({"alignment": {"tilt": -0.1}}, "uncertainty.alignment.tilt must be >= 0"),
    ({"alignment": {"offset": -1}}, "uncertainty.alignment.offset must be >= 0"),
    ({"alignment": {"tilt": 20}}, "uncertainty.alignment.tilt must be >= 0 and <= 10"),
    ({"alignment": {"twist": 1}}, "twist"),
])
def test_bad_alignment_entries_are_refused_naming_the_field(table, needle):
    with pytest.raises(SceneError, match=needle.replace(".", r"\.")):
        parse_scene(_source(uncertainty=table))


@pytest.mark.parametrize("misalignment, grips, needle", [
    ({"tilt": 90}, "clamped", "test.misalignment.tilt must be > -90 and < 90"),
    ({"tilt": -95}, "clamped", "test.misalignment.tilt must be > -90 and < 90"),
    ({"offset": "1"}, "clamped", "test.misalignment.offset must be a number"),
    ({"tilt": 1}, "roller", "test.misalignment applies to a uniaxial test in clamped grips"),
])
def test_bad_misalignment_is_refused_naming_the_field(misalignment, grips, needle):
    with pytest.raises(SceneError, match=needle.replace(".", r"\.")):
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
