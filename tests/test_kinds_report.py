"""Reports of planar and simple-shear tests show their own curves and quantities, not a uniaxial
test's (no E, ν or apparent Poisson's ratio where the width is held or sheared)."""

from __future__ import annotations

import json

import pytest

from vlab.report.outcome import outcome_of
from vlab.report.writer import ReportOptions, write_report
from vlab.run import run_scene
from vlab.scene import parse_scene

OPTIONS = ReportOptions(render=False, vtu=False)


def scene(model: str, test: dict):
    return parse_scene({"name": "kinds-report", "specimen": {"shape": "block", "size": [4.0, 3.0, 2.0]},
                        "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": model, "E": 3.0, "nu": 0.45},
                        "test": {"steps": 3} | test})


@pytest.mark.parametrize("test,shown,hidden", [
    ({"kind": "simple-shear", "shear": 0.3}, ["G measured (gauge marks)", "N₁ = σ₁₁ − σ₂₂", "force at max shear"],
     ["ν measured", "E measured", "−ε_lat", "s_NH"]),
    ({"kind": "planar", "stretch": 1.3}, ["planar modulus measured", "ν measured", "force at max stretch"],
     ["−ε_lat", "s_NH"]),
], ids=["simple-shear", "planar"])
def test_a_new_kind_report_draws_its_own_curves_for_several_models(tmp_path, test, shown, hidden):
    outcomes = [outcome_of(run_scene(scene(model, test))) for model in ("neo-hookean", "stvk-volumetric")]
    write_report(outcomes, tmp_path / "r", scene("neo-hookean", test), None, OPTIONS)
    page = (tmp_path / "r" / "index.html").read_text(encoding="utf-8")
    files = {p.name for p in (tmp_path / "r").iterdir()}
    assert "stress_strain.png" in files and "lateral_strain.png" not in files
    for text in shown:
        assert text in page, text
    for text in hidden:
        assert text not in page, text
    data = json.loads((tmp_path / "r" / "neo-hookean" / "results.json").read_text(encoding="utf-8"))
    key = "G" if test["kind"] == "simple-shear" else "planar_modulus"
    assert data["measured"][key] is not None and data["measured"]["units"][key] == "MPa"


def test_a_uniaxial_report_keeps_its_lateral_strain_figure(tmp_path):
    outcome = outcome_of(run_scene(scene("neo-hookean", {"kind": "uniaxial", "stretch": 1.2})))
    write_report([outcome], tmp_path / "r", scene("neo-hookean", {"kind": "uniaxial", "stretch": 1.2}), None, OPTIONS)
    assert (tmp_path / "r" / "lateral_strain.png").exists()
    assert "ν measured" in (tmp_path / "r" / "index.html").read_text(encoding="utf-8")


def test_a_planar_load_unload_report_adds_the_hysteresis_loop(tmp_path):
    raw = {"name": "planar-mullins", "specimen": {"shape": "block", "size": [4.0, 3.0, 2.0]},
           "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.45},
           "test": {"kind": "planar", "stretch": 1.4, "steps": 3, "protocol": "load-unload"},
           "effects": {"mullins": {"r": 2.0, "m": 0.5}}}
    s = parse_scene(raw)
    write_report([outcome_of(run_scene(s))], tmp_path / "r", s, None, OPTIONS)
    assert (tmp_path / "r" / "hysteresis.png").exists() and not (tmp_path / "r" / "lateral_strain.png").exists()


@pytest.mark.parametrize("test,effects,figure", [
    ({"protocol": "cyclic", "shear": [0.2, 0.4], "steps": 4}, {"mullins": {"r": 2.0, "m": 0.5}}, "hysteresis.png"),
    ({"protocol": "relaxation", "shear": 0.2, "ramp_time": 1.0, "hold_time": 5.0, "hold_steps": 3, "steps": 3},
     {"viscoelastic": {"tau": [1.0], "beta": [0.5]}}, "relaxation.png"),
], ids=["mullins-cycles", "viscoelastic-relaxation"])
def test_a_simple_shear_report_with_effects_plots_shear_force_and_stress_against_gamma_and_time(
        tmp_path, test, effects, figure):
    raw = {"name": "shear-effects", "specimen": {"shape": "block", "size": [4.0, 3.0, 2.0]},
           "mesh": {"size": 2.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.45},
           "test": {"kind": "simple-shear", "grips": "kinematic"} | test, "effects": effects}
    s = parse_scene(raw)
    write_report([outcome_of(run_scene(s))], tmp_path / "r", s, None, OPTIONS)
    assert (tmp_path / "r" / figure).exists()


def test_a_single_model_report_shows_no_departure_rows_since_nothing_is_compared(tmp_path):
    test = {"kind": "uniaxial", "stretch": 1.2}
    write_report([outcome_of(run_scene(scene("neo-hookean", test)))], tmp_path / "r", scene("neo-hookean", test),
                 None, OPTIONS)
    assert "s_NH" not in (tmp_path / "r" / "index.html").read_text(encoding="utf-8")


def test_an_inflation_report_names_its_pressure_maximum_or_says_there_is_none():
    from vlab.report.kind_rows import kind_rows

    def data(limit):
        return {"scene": {"source": {"test": {"kind": "inflation"}}},
                "measured": {"limit_point": limit, "initial_slope": 0.3943, "pressure_at_end": 0.0316,
                             "stretch_at_end": 2.5}}

    rows = dict(kind_rows([data({"stretch": 1.4261, "pressure": 0.047195, "bracket": [1.4, 1.5]}), data(None)]))
    peak, none = rows["pressure maximum (limit point)"]
    assert "λ_a = 1.4261" in peak and "p = 0.047195 MPa" in peak and "1.4 and 1.5" in peak
    assert none == "none in the recorded range"
    assert rows["initial slope dp/dλ_a [MPa]"] == ["0.3943", "0.3943"]
