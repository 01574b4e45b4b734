"""`vlab budget`: the [uncertainty] table's validation and the budget against the analytic GUM of
E = F L0 / (A ΔL) on a homogeneous block (every FE run exact, so E is a known product of the
perturbations)."""

import json
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.fields import SceneError
from vlab.scene import parse_scene
from vlab.study.summary import RunKnobs, summarize
from vlab.uncertainty.analysis import monte_carlo, sobol_first_order
from vlab.uncertainty.budget import compute_budget
from vlab.uncertainty.model import lab_values, sample_deltas
from vlab.uncertainty.spec import parse_uncertainty

BLOCK = {"name": "block-budget", "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
         "mesh": {"size": 10.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
         "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.003, "steps": 2}}
UNC = {"samples": 16, "width": 0.1, "thickness": 0.05, "load_cell_class": 1, "extensometer_class": 0.5,
       "resolution": False}


def _scene(unc=None, base=BLOCK):
    return parse_scene(dict(base, uncertainty=dict(unc if unc is not None else UNC)))


def _in_process(points, what):
    """The sweep's contract without a Dask cluster (the CLI test below runs the real one)."""
    s = [summarize(p.source, RunKnobs(), p.label, p.base_dir) | {"cache_hit": False} for p in points]
    return SimpleNamespace(summaries=s, cache_hits=0, computed=len(s), seconds={})


def _analytic_relative_u(spec) -> float:
    """u(E)/E of E = F L0/(A ΔL): √Σ relative variances (width, thickness, load cell, extensometer, gauge)."""
    n = spec.nominal
    rel = {"width": 1 / n["width"], "thickness": 1 / n["thickness"], "load_cell": 1.0, "extensometer": 1.0,
           "gauge_rel": 1.0}
    return math.sqrt(sum((s.u * rel[s.kind]) ** 2 for s in spec.sources if s.kind in rel))


def test_block_budget_reproduces_the_analytic_gum_combination():
    scene = _scene()
    spec = parse_uncertainty(scene.source["uncertainty"], scene)
    budget, runs = compute_budget(scene.source, spec, ".", _in_process, scene.measure.modulus_window[0])
    E0 = budget["E"]["nominal"]
    expect = _analytic_relative_u(spec)
    # the linearised budget from paired runs is the analytic combination (up to the O(u²) of the
    # central difference of 1/L_e)
    assert budget["E"]["gum"]["u"] / E0 == pytest.approx(expect, rel=1e-4)
    shares = {r["input"]: r["share"] for r in budget["E"]["contributions"]}
    assert shares["load cell"] == pytest.approx((spec.sources[2].u / expect) ** 2, rel=1e-4)
    assert shares["extensometer (transverse)"] == pytest.approx(0.0, abs=1e-12)
    # every virtual test is exact (a homogeneous block), so each sample's E is the product formula
    n = spec.nominal
    for d, s, E in zip(runs.deltas, runs.summaries, runs.E):
        assert s["measured"]["E"] == pytest.approx(E0, rel=1e-8)
        W, T = n["width"] + d["specimen width"], n["thickness"] + d["specimen thickness"]
        Le = n["gauge_length"] * (1 + d["extensometer gauge length (class)"])
        assert E == pytest.approx(s["measured"]["E"] * W * T / (n["width"] * n["thickness"]) * n["gauge_length"] / Le
                                  * (1 + d["load cell"]) / (1 + d["extensometer (axial)"]), rel=1e-12)
    # the 16 FE samples' spread agrees within 4 of its own stated statistical errors
    q = budget["E"]
    assert abs(q["u"] / (expect * E0) - 1) < 4 * q["statistical_error"]["u_relative"]
    assert q["U"] == 2 * q["u"] and q["quantiles"]["2.5%"] < q["mean"] < q["quantiles"]["97.5%"]


def test_the_monte_carlo_of_the_lab_model_converges_to_the_gum_and_sobol_to_the_shares():
    """E_run is the same for every sample of the block (checked above), so the distribution of E is
    that of the lab's analysis over the draws: 5000 of them pin u to ~1 %."""
    scene = _scene()
    spec = parse_uncertainty(scene.source["uncertainty"], scene)
    measured = {"E": 10.0, "nu": 0.3}
    deltas = [sample_deltas(spec, i) for i in range(5000)]
    y = np.array([lab_values(measured, spec, d)[0] for d in deltas])
    mc = monte_carlo(y)
    expect = _analytic_relative_u(spec) * 10.0
    assert abs(mc["u"] / expect - 1) < 3 * mc["statistical_error"]["u_relative"]
    assert mc["statistical_error"]["u_relative"] < 0.012
    X = np.array([[d[s.name] for s in spec.sources] for d in deltas])
    rel = {"width": 0.1, "thickness": 0.1, "load_cell": 1.0, "extensometer": 1.0, "gauge_rel": 1.0, "transverse": 0}
    for (S, err), s in zip(sobol_first_order(X, y), spec.sources):
        share = (s.u * rel[s.kind] * 10.0 / expect) ** 2
        assert abs(S - share) < max(4 * err, 0.01), s.name


def test_defaults_come_from_the_specimen_standard():
    base = {"name": "d", "specimen": {"shape": "dogbone", "standard": "ISO 527-2 1BA"}, "mesh": {"size": 1.25},
            "material": {"model": "stvk-volumetric", "E": 2500.0, "nu": 0.35},
            "test": {"kind": "uniaxial", "stretch": 1.005}}
    scene = _scene({}, base)
    spec = parse_uncertainty({}, scene)
    by = {s.name: s for s in spec.sources}
    assert by["specimen width"].half_width == 0.5 and "ISO 527-2 1BA" in by["specimen width"].source
    assert "specimen thickness" not in by  # the standard gives h >= 2 only
    assert by["load cell"].half_width == 0.01 and by["extensometer (axial)"].half_width == 0.01
    assert spec.samples == 200 and spec.nominal == {"width": 5.0, "thickness": 2.0, "gauge_length": 25.0}


@pytest.mark.parametrize("unc,needle", [
    ({"width": -0.1}, "uncertainty.width must be >= 0"),
    ({"load_cell_class": 1.5}, "uncertainty.load_cell_class must be a ISO 7500-1 class (0.5, 1, 2, 3)"),
    ({"extensometer_class": 3}, "uncertainty.extensometer_class must be a ISO 9513 class (0.2, 0.5, 1, 2)"),
    ({"samples": 0}, "uncertainty.samples"),
    ({"thickness": 10.0}, "uncertainty.thickness = 10 mm is not smaller than the dimension itself (10 mm)"),
    ({"micrometer": 20.0}, "uncertainty.micrometer = 20 mm is not smaller than the width"),
    ({"window_shift": 0.001}, "uncertainty.window_shift = 0.001 must be below the window's start"),
    ({"material": {"mu": 0.1}}, "uncertainty.material"),
    ({"material": {"E": 0.7}}, "uncertainty.material.E"),
    ({"widht": 0.1}, "widht"),
])
def test_bad_uncertainty_tables_are_refused_naming_the_field(unc, needle):
    with pytest.raises(SceneError) as exc:
        _scene(unc)
    assert needle in str(exc.value)


def _toml_value(v) -> str:
    return json.dumps(v) if not isinstance(v, dict) else "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"


def _write_scene(tmp_path: Path, unc: dict) -> Path:
    lines = [f'name = "{BLOCK["name"]}"']
    for section, table in list(BLOCK.items())[1:] + [("uncertainty", unc)]:
        lines.append(f"[{section}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in table.items()]
    f = tmp_path / "s.toml"
    f.write_text("\n".join(lines) + "\n")
    return f


@pytest.mark.parametrize("unc,args,needle", [
    ({"width": -0.1}, [], "uncertainty.width must be >= 0"),
    ({"load_cell_class": 7}, [], "ISO 7500-1 class"),
    ({"samples": 0}, [], "uncertainty.samples"),
    ({"width": 12.0}, [], "not smaller than the dimension itself"),
    ({}, ["--samples", "0"], "--samples 0: must be 1..100000"),
    ({"load_cell_class": "none", "extensometer_class": "none"}, [], "there is nothing to budget"),
])
def test_cli_bad_input_exits_2_and_writes_nothing(tmp_path, unc, args, needle):
    f = _write_scene(tmp_path, unc)
    res = CliRunner().invoke(app, ["budget", str(f), "--out", str(tmp_path / "out"),
                                   "--cache", str(tmp_path / "c"), *args])
    assert res.exit_code == 2, res.output
    assert needle in " ".join(res.output.split())
    assert not (tmp_path / "out").exists()


def test_vlab_run_validates_the_table_too(tmp_path):
    f = _write_scene(tmp_path, {"extensometer_class": 0.3})
    res = CliRunner().invoke(app, ["run", str(f), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2 and "ISO 9513 class" in " ".join(res.output.split())


@pytest.mark.slow
def test_cli_budget_on_dask_writes_the_folder_and_resumes_from_the_cache(tmp_path):
    f = _write_scene(tmp_path, dict(UNC, samples=6))
    args = ["budget", str(f), "--out", str(tmp_path / "out"), "--cache", str(tmp_path / "c"), "-j", "2", "-q"]
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 0, res.output
    d = json.loads((tmp_path / "out" / "budget.json").read_text())
    assert d["runs"]["computed"] == d["runs"]["paired"] + 6
    for name in ("samples.csv", "index.html", "tornado_E.png", "tornado_nu.png", "histogram.png"):
        assert (tmp_path / "out" / name).is_file()
    again = CliRunner().invoke(app, args + ["--force"])
    assert again.exit_code == 0
    d2 = json.loads((tmp_path / "out" / "budget.json").read_text())
    assert d2["runs"]["computed"] == 0 and d2["E"]["mean"] == d["E"]["mean"]
