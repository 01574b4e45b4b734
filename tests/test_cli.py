"""The command line: a run writes its report; invalid scenes exit non-zero, name the field and
leave nothing behind; vlab moduli prints all six constants."""

import json
import subprocess
import sys

import pytest
from typer.testing import CliRunner

from vlab.cli import app

runner = CliRunner()

VALID = """
name = "cli-block"
[specimen]
shape = "block"
size = [10.0, 10.0, 10.0]
[mesh]
size = 5.0
order = 1
cell = "hex"
[material]
model = "neo-hookean"
E = 10.0
nu = 0.3
[test]
kind = "uniaxial"
grips = "roller"
stretch = 1.2
steps = 3
"""

INVALID = [
    ("nu = 0.3", "nu = 0.5", "material.nu"),
    ("nu = 0.3", "nu = 0.7", "material.nu"),
    ("E = 10.0", "E = -1.0", "material.E"),
    ('model = "neo-hookean"', 'model = "mooney"', "material.model"),
    ("stretch = 1.2", "strech = 1.2", "stretch"),
    ("stretch = 1.2", "stretch = -0.5", "test.stretch"),
    ("stretch = 1.2", "stretch = 0.0", "test.stretch"),
    ("steps = 3", "steps = 0", "test.steps"),
]


def _write(tmp_path, text):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return path


def test_run_writes_results_curve_plot_and_report(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(_write(tmp_path, VALID)), "--out", str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    data = json.loads((out / "results.json").read_text())
    assert data["converged"] is True
    for key in ("E", "nu"):
        assert data["measured"][key] is not None
    curve = data["curve"]
    assert len(curve["stretch"]) == len(curve["strain"]) == len(curve["stress"]) == len(curve["force"])
    assert len(curve["transverse_strain"]) == len(curve["stretch"])
    assert len(data["solver"]["newton_iterations"]) == len(curve["stretch"])
    assert data["timing"]["total_s"] > 0 and data["mesh"]["dofs"] == 81
    for name in ("curve.csv", "stress_strain.png", "index.html", "scene.toml"):
        assert (out / name).stat().st_size > 0
    assert (out / "curve.csv").read_text().splitlines()[0].startswith("stretch,strain,stress")


@pytest.mark.parametrize("old,new,field", INVALID)
def test_invalid_scene_names_the_field_and_writes_nothing(tmp_path, old, new, field):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(_write(tmp_path, VALID.replace(old, new))), "--out", str(out)])
    assert res.exit_code == 2
    assert field in res.output
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".out")]


def test_missing_key_is_an_error_not_a_default(tmp_path):
    res = runner.invoke(app, ["run", str(_write(tmp_path, VALID.replace("stretch = 1.2", ""))),
                              "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "test.stretch" in res.output


def test_failed_test_exits_non_zero_with_its_cause_in_results(tmp_path):
    text = VALID.replace('"neo-hookean"', '"stvk"').replace("stretch = 1.2", "stretch = 2.5")
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(_write(tmp_path, text)), "--out", str(out), "--quiet"])
    assert res.exit_code == 1
    failure = json.loads((out / "results.json").read_text())["failure"]
    assert {"step", "stretch", "reason", "residual_history"} <= set(failure)
    assert "test stopped" in res.output


def test_moduli_prints_all_six_constants():
    res = runner.invoke(app, ["moduli", "--E", "10", "--nu", "0.3"])
    assert res.exit_code == 0
    for name, value in (("lambda", "5.769230769"), ("mu", "3.846153846"), ("K", "8.333333333"), ("M", "13.46153846")):
        assert name in res.output and value in res.output


def test_moduli_rejects_a_bad_pair_with_the_field_named():
    res = runner.invoke(app, ["moduli", "--E", "10", "--nu", "0.5"])
    assert res.exit_code == 2 and "nu" in res.output


def test_python_dash_m_vlab_runs_the_built_in_default_scene(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "vlab", "run", "--out", str(tmp_path / "r"), "--quiet"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert json.loads((tmp_path / "r" / "results.json").read_text())["scene"]["name"] == "block-neo-hookean"
