"""The rubber models in scenes: the card grammar and its errors, the roller block against the
analytic homogeneous curve, the incompressible limit, mixed formulation, sheets, effects, and
what results.json reports."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from rubber_cards import NAMES, card, law
from scenes import scene_dict
from vlab.cli import app
from vlab.fields import SceneError
from vlab.materials.homogeneous import biaxial, planar, uniaxial
from vlab.run import run_scene
from vlab.scene import parse_scene

STRETCHES = {"uniaxial-tension": 1.8, "uniaxial-compression": 0.7,
             "biaxial-tension": [1.5, 1.3], "biaxial-compression": [0.85, 0.9]}


def run(name: str, stretch, **sections):
    kind = "biaxial" if isinstance(stretch, list) else "uniaxial"
    raw = scene_dict(material=card(name), test={"kind": kind, "stretch": stretch, "steps": 4}, **sections)
    raw["material"] = card(name)
    return run_scene(parse_scene(raw))


@pytest.mark.parametrize("case", list(STRETCHES))
@pytest.mark.parametrize("name", NAMES)
def test_the_roller_block_follows_the_analytic_homogeneous_curve_at_every_step(name, case):
    result = run(name, STRETCHES[case])
    assert result.converged, result.history.failure
    ref = result.reference
    for axis, key in ((0, "stress_x"), (1, "stress_y")):
        if key not in ref:
            continue
        fe, exact = np.asarray(result.curve.column("stress", axis)), np.asarray(ref[key])
        assert len(fe) == len(exact) >= 4
        np.testing.assert_allclose(fe, exact, rtol=1e-6, atol=1e-12)


# --- incompressible limit: the closed forms with W₁, W₂ written out independently ------------

def _w(name: str, I1: float, I2: float) -> tuple[float, float]:
    """(∂W/∂Ī₁, ∂W/∂Ī₂) of the test cards (rubber_cards), by hand."""
    if name == "mooney-rivlin":
        return 0.3, 0.08
    if name == "yeoh":
        x = I1 - 3.0
        return 0.4 - 0.04 * x + 0.012 * x * x, 0.0
    if name == "gent":
        return 0.5 / (2.0 * (1.0 - (I1 - 3.0) / 12.0)), 0.0
    C = (1 / 2, 1 / 20, 11 / 1050, 19 / 7000, 519 / 673750)
    return 0.45 * sum((i + 1) * c * I1**i / 2.8 ** (2 * i) for i, c in enumerate(C)), 0.0


def incompressible_uniaxial(name: str, lam: float) -> float:
    if name == "ogden":
        return sum(2 * m / a * (lam ** (a - 1) - lam ** (-a / 2 - 1)) for m, a in zip(*_ogden()))
    W1, W2 = _w(name, lam**2 + 2 / lam, 2 * lam + lam**-2)
    return 2 * (lam - lam**-2) * (W1 + W2 / lam)


def incompressible_equibiaxial(name: str, lam: float) -> float:
    if name == "ogden":
        return sum(2 * m / a * (lam ** (a - 1) - lam ** (-2 * a - 1)) for m, a in zip(*_ogden()))
    W1, W2 = _w(name, 2 * lam**2 + lam**-4, lam**4 + 2 * lam**-2)
    return 2 * (lam - lam**-5) * (W1 + lam**2 * W2)


def incompressible_planar(name: str, lam: float) -> float:
    """Pure shear F = diag(λ, 1, 1/λ): Ī₁ = Ī₂ = λ² + 1 + λ⁻², P₁₁ = 2 (λ − λ⁻³)(W₁ + W₂)."""
    if name == "ogden":
        return sum(2 * m / a * (lam ** (a - 1) - lam ** (-a - 1)) for m, a in zip(*_ogden()))
    I = lam**2 + 1 + lam**-2
    W1, W2 = _w(name, I, I)
    return 2 * (lam - lam**-3) * (W1 + W2)


def _ogden():
    return (0.63, 0.0012, -0.01), (1.3, 5.0, -2.0)


@pytest.mark.parametrize("lam", [0.6, 0.8, 1.3, 2.0, 2.6])
@pytest.mark.parametrize("name", NAMES)
def test_in_the_incompressible_limit_the_nominal_stress_approaches_the_closed_forms(name, lam):
    """Uniaxial, equibiaxial and planar (pure shear) at K/μ0 = 1e4, to 1e-3."""
    m = law(name, K=1e4 * law(name).mu0)
    u = uniaxial(m, lam).nominal_stress
    assert u == pytest.approx(incompressible_uniaxial(name, lam), rel=1e-3)
    if 0.8 <= lam <= 2.0:  # equibiaxial 2.6 locks Gent (Ī₁ − 3 > 12); 0.6 thickens the sheet 2.8×
        b = biaxial(m, lam, lam).nominal_stress
        assert b == pytest.approx(incompressible_equibiaxial(name, lam), rel=1e-3)
    p = planar(m, lam).P[0, 0]
    assert p == pytest.approx(incompressible_planar(name, lam), rel=1e-3)


# --- small strain through the whole lab -------------------------------------------------------

@pytest.mark.parametrize("name", NAMES)
def test_the_lab_measures_the_E_and_nu_the_card_implies_at_small_strain(name):
    raw = scene_dict(test={"stretch": 1.00002, "steps": 2}, measure={"modulus_window": [1e-6, 1e-5]})
    raw["material"] = card(name, nu=0.3)
    result = run_scene(parse_scene(raw))
    m = law(name, nu=0.3)
    assert result.constants.E == pytest.approx(m.youngs_modulus, rel=1e-4)
    assert result.constants.nu == pytest.approx(0.3, rel=1e-4)


# --- formulations, sheets, effects ---------------------------------------------------------

@pytest.mark.parametrize("name", NAMES)
def test_the_mixed_formulation_runs_every_rubber_model_and_matches_the_analytic_block(name):
    result = run(name, 1.6, mesh={"formulation": "mixed"})
    assert result.converged
    np.testing.assert_allclose(result.curve.column("stress", 0), result.reference["stress_x"], rtol=1e-6)


@pytest.mark.parametrize("name", NAMES)
def test_a_sheet_in_plane_stress_matches_the_3d_uniaxial_state(name):
    raw = scene_dict(specimen={"shape": "sheet", "size": [20.0, 10.0], "thickness": 1.0},
                     mesh={"size": 5.0, "cell": "quad"}, test={"stretch": 1.5, "steps": 3})
    raw["material"] = card(name)
    result = run_scene(parse_scene(raw))
    exact = [uniaxial(law(name), s).nominal_stress for s in result.curve.stretch[0]]
    np.testing.assert_allclose(result.curve.column("stress", 0), exact, rtol=1e-6)


@pytest.mark.parametrize("name", ["ogden", "mooney-rivlin"])
def test_mullins_softening_over_a_rubber_ground_law_unloads_below_the_loading_path(name):
    raw = scene_dict(test={"stretch": 1.6, "steps": 4, "protocol": "load-unload"},
                     effects={"mullins": {"r": 2.0, "m": 0.05}})
    raw["material"] = card(name)
    result = run_scene(parse_scene(raw))
    assert result.converged
    stress, stretch = np.asarray(result.curve.column("stress", 0)), np.asarray(result.curve.stretch[0])
    peak = int(np.argmax(stretch))
    up = np.interp(1.3, stretch[:peak + 1], stress[:peak + 1])
    down = np.interp(1.3, stretch[peak:][::-1], stress[peak:][::-1])
    assert down < 0.9 * up


@pytest.mark.parametrize("name", ["yeoh", "gent"])
def test_viscoelastic_branches_over_a_rubber_ground_law_stiffen_a_fast_test(name):
    def final_stress(beta):
        raw = scene_dict(test={"stretch": 1.4, "steps": 4, "ramp_time": 0.1},
                         effects={"viscoelastic": {"tau": [1.0], "beta": [beta]}})
        raw["material"] = card(name)
        return run_scene(parse_scene(raw)).curve.column("stress", 0)[-1]

    elastic = uniaxial(law(name), 1.4).nominal_stress
    assert final_stress(0.0) == pytest.approx(elastic, rel=1e-6)
    assert final_stress(1.0) > 1.3 * elastic


# --- results.json ------------------------------------------------------------------------

def test_results_json_reports_mu0_K_and_the_small_strain_E_and_nu(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('name = "og"\n[specimen]\nshape = "block"\nsize = [10.0, 10.0, 10.0]\n[mesh]\nsize = 5.0\n'
                    'cell = "hex"\n[material]\nmodel = "ogden"\nmu = [0.63, 0.0012, -0.01]\n'
                    'alpha = [1.3, 5.0, -2.0]\nD1 = 0.002\n[test]\nkind = "uniaxial"\nstretch = 1.2\nsteps = 2\n')
    res = CliRunner().invoke(app, ["run", str(path), "--out", str(tmp_path / "out"), "-q", "--no-render",
                                   "--no-estimate"])
    assert res.exit_code == 0, res.output
    data = json.loads((tmp_path / "out" / "results.json").read_text())
    small = data["input"]["small_strain"]
    m = law("ogden", D1=0.002)
    assert small["mu0"] == pytest.approx(0.6212) and small["K"] == pytest.approx(1000.0)
    assert small["E"] == pytest.approx(m.youngs_modulus) and small["nu"] == pytest.approx(m.poisson_ratio)
    assert data["input"]["parameters"] == {"mu": [0.63, 0.0012, -0.01], "alpha": [1.3, 5.0, -2.0]}
    assert data["input"]["volumetric"] == "quadratic" and data["input"]["bulk_as_given"] == {"D1": 0.002}


# --- vlab compare: any set of cards side by side -----------------------------------------------

def _compare_scene(tmp_path) -> Path:
    text = (Path(__file__).resolve().parents[1] / "specimens" / "block-rubber-compare.toml").read_text()
    path = tmp_path / "cmp.toml"
    path.write_text(text.replace("steps = 10", "steps = 2").replace("stretch = 3.0", "stretch = 1.5"))
    return path


def test_compare_runs_the_scene_cards_side_by_side_under_their_labels(tmp_path):
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["compare", str(_compare_scene(tmp_path)), "--models", "neo-hookean,gent",
                                   "--out", str(out), "-q", "-j", "1", "--no-render"])
    assert res.exit_code == 0, res.output
    summary = json.loads((out / "comparison.json").read_text())
    assert summary["models"] == ["neo-hookean", "gent"]
    for label, model in (("neo-hookean", "mooney-rivlin"), ("gent", "gent")):
        data = json.loads((out / label / "results.json").read_text())
        assert data["input"]["model"] == model
        assert data["input"].get("label", model) == label  # a label equal to its model is not repeated
        assert data["input"]["small_strain"]["mu0"] == pytest.approx(0.6)
        np.testing.assert_allclose(data["curve"]["stress"], data["reference"]["stress_x"], rtol=1e-6)


def test_compare_without_models_runs_every_card_of_the_scene():
    from vlab.compare import compare_labels
    from vlab.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "specimens" / "block-rubber-compare.toml")
    assert compare_labels(scene) == ("neo-hookean", "mooney-rivlin", "yeoh", "ogden", "gent", "arruda-boyce")


def test_compare_refuses_a_card_model_without_its_card_and_a_bad_card(tmp_path):
    path = _compare_scene(tmp_path)
    res = CliRunner().invoke(app, ["compare", str(path), "--models", "linear,nope", "--out",
                                   str(tmp_path / "o1"), "-q"])
    assert res.exit_code == 2 and "'nope'" in res.output and not (tmp_path / "o1").exists()
    bad = tmp_path / "bad.toml"
    bad.write_text(path.read_text().replace("Jm = 20.0", "Jm = -1.0"))
    res = CliRunner().invoke(app, ["compare", str(bad), "--out", str(tmp_path / "o2"), "-q"])
    assert res.exit_code == 2 and "compare.gent.Jm must be > 0" in res.output
    assert not (tmp_path / "o2").exists()
    with pytest.raises(SceneError, match="takes its own constants"):
        from vlab.compare import scene_for_model
        from vlab.scene import load_scene
        scene_for_model(load_scene(Path(__file__).resolve().parents[1] / "specimens" / "block-neo-hookean.toml"),
                        "yeoh")
