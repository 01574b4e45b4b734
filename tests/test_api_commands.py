"""The Python API's commands (vlab.fit, compare, sweep, cost, stability, export) return what the
command line writes: each is run on small inputs and its fields compared with the CLI's JSON on
the same input (wall times, dates and cache counters aside: they differ between any two runs)."""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

import vlab
from vlab.cli import app
from helpers_scenes import block_toml

ROOT = Path(__file__).resolve().parents[1]
TRELOAR = ROOT / "specimens" / "treloar1944" / "treloar-uniaxial.toml"
runner = CliRunner()
#: fields that differ between two runs of the same input (clocks, dates, peak memory, cache
#: bookkeeping: a cost study's points that are the same scene share one cache entry, so a cached
#: study shows the one run's time and memory twice where the first study measured two)
VOLATILE = {"timing", "fit_s", "seconds", "total_seconds", "date", "cache_hit", "cache_hits", "computed", "files",
            "cached", "wall_s", "total_s", "memory"}
TINY = block_toml("api-tiny", material='model = "neo-hookean"\nE = 10.0\nnu = 0.3', mesh='size = 5.0\ncell = "hex"',
                  stretch=1.1, steps=2)


def steady(o):
    """``o`` without the VOLATILE fields (at any depth)."""
    if isinstance(o, dict):
        return {k: steady(v) for k, v in o.items() if k not in VOLATILE}
    if isinstance(o, list):
        return [steady(v) for v in o]
    return o


def cli(*args) -> None:
    res = runner.invoke(app, [str(a) for a in args])
    assert res.exit_code in (0, 3), res.output  # 3: vlab fit's converged card that is not trustworthy


def read_json(path: Path):
    return json.loads(path.read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def tiny(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("scene") / "tiny.toml"
    path.write_text(TINY, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """(vlab.fit of the shipped Treloar fit file, the folder `vlab fit` wrote for it)."""
    out = tmp_path_factory.mktemp("fit") / "fit"
    cli("fit", TRELOAR, "--out", out)
    return vlab.fit(TRELOAR), out


def test_fit_has_the_fields_of_fit_json(fitted):
    fit, out = fitted
    on_disk = read_json(out / "fit.json")
    assert set(fit.fields) == set(on_disk) - {"files"}
    assert steady(fit.data) == steady(on_disk)
    assert fit.converged == on_disk["converged"] and fit["parameters"] == on_disk["parameters"]
    assert fit.card_toml == (out / "card.toml").read_text()
    with pytest.raises(AttributeError, match="no field 'paramters'.*parameters"):
        fit.paramters


def test_fit_data_as_a_dataframe(fitted):
    pd = pytest.importorskip("pandas")
    fit, out = fitted
    table = fit.to_pandas()
    assert isinstance(table, pd.DataFrame)
    assert len(table) == sum(d["points"] for d in read_json(out / "fit.json")["datasets"])
    assert set(table["dataset"]) == {"uniaxial", "equibiaxial", "pure_shear"}
    uniaxial = table[table["dataset"] == "uniaxial"]
    rms = float((uniaxial["relative_residual"] ** 2).mean() ** 0.5)
    assert rms == pytest.approx(fit.datasets[0]["rms_relative"], rel=1e-6)


def test_a_ranking_has_the_rows_of_ranking_json(tmp_path):
    pytest.importorskip("pandas")
    out = tmp_path / "rank"
    cli("fit", TRELOAR, "--models", "neo-hookean,mooney-rivlin", "--out", out)
    ranking = vlab.fit(TRELOAR, models=["neo-hookean", "mooney-rivlin"])
    assert isinstance(ranking, vlab.Ranking)
    assert steady(ranking.data) == steady(read_json(out / "ranking.json"))
    for model, fit in ranking.fits.items():
        assert steady(fit.data) == steady(read_json(out / model / "fit.json"))
    assert ranking.best.data is ranking.fits[ranking.ranking[0]["model"]].data
    assert list(ranking.to_pandas()["model"]) == [r["model"] for r in ranking.ranking]


def test_export_gives_the_texts_vlab_export_writes(fitted, tmp_path, monkeypatch):
    fit, folder = fitted
    monkeypatch.chdir(tmp_path)
    cli("export", folder, "--to", "abaqus,felupe")
    cards = vlab.export(folder, ["abaqus", "felupe"])
    assert cards.fields == ("abaqus", "felupe")
    assert cards["abaqus"] == (tmp_path / "abaqus.inp").read_text(encoding="utf-8")
    assert cards["felupe"] == (tmp_path / "felupe.py").read_text(encoding="utf-8")
    from_result = vlab.export(fit, "abaqus")["abaqus"]  # a fit result, before any folder
    numbers = [line for line in cards["abaqus"].splitlines() if not line.startswith("**")]
    assert [line for line in from_result.splitlines() if not line.startswith("**")] == numbers
    assert cards.write(tmp_path / "cards")["abaqus"].read_text(encoding="utf-8") == cards["abaqus"]


def test_export_refuses_a_bad_solver_naming_the_allowed_ones(fitted):
    with pytest.raises(vlab.SceneError, match="unknown solver nastran; allowed: abaqus"):
        vlab.export(fitted[1], "nastran")


def test_compare_has_comparison_json_and_each_models_results(tiny, tmp_path):
    out = tmp_path / "compare"
    cli("compare", tiny, "--models", "linear,neo-hookean", "--no-render", "--workers", "1", "--quiet", "--out", out)
    both = vlab.compare(tiny, models=["linear", "neo-hookean"], workers=1)
    on_disk = read_json(out / "comparison.json")
    assert both.models == on_disk["models"] == ["linear", "neo-hookean"]
    assert both.departures_from_neo_hookean == on_disk["departures_from_neo_hookean"] != {}
    for model, result in both.results.items():
        assert steady(result.data) == steady(read_json(out / model / "results.json"))
    with pytest.raises(ValueError, match="write the comparison's report"):
        both.results["linear"].write_report(tmp_path / "one")


def test_compare_names_an_unknown_model(tiny):
    with pytest.raises(vlab.SceneError, match="models 'linear,nope': unknown 'nope'; allowed: .*neo-hookean"):
        vlab.compare(tiny, models="linear,nope")


def test_sweep_has_sweep_json_and_its_table(tiny, tmp_path):
    pd = pytest.importorskip("pandas")
    cache, out = tmp_path / "cache", tmp_path / "sweep"
    cli("sweep", tiny, "--set", "material.nu=0.3,0.4", "--workers", "1", "--cache", cache, "--quiet", "--out", out)
    table = vlab.sweep(tiny, {"material.nu": [0.3, 0.4]}, cache=cache, workers=1)  # the CLI's runs, cached
    on_disk = read_json(out / "sweep.json")
    assert table.meta["cache_hits"] == 2 and table.meta["grid"] == on_disk["meta"]["grid"]
    assert steady(table.data) == steady(on_disk)
    with open(out / "sweep.csv", newline="", encoding="utf-8") as fh:
        headers, *rows = list(csv.reader(fh))
    assert table.headers == headers
    frame = table.to_pandas()
    assert isinstance(frame, pd.DataFrame) and list(frame.columns) == headers
    assert list(frame["material.nu"]) == [0.3, 0.4] and list(frame["status"]) == ["ok", "ok"]
    assert [float(r[headers.index("E [MPa]")]) for r in rows] == list(frame["E [MPa]"])


def test_cost_has_cost_json_and_its_table(tiny, tmp_path):
    pd = pytest.importorskip("pandas")
    cache, out = tmp_path / "cache", tmp_path / "cost"
    cli("cost", tiny, "--levels", "3", "--orders", "1", "--cells", "hex", "--workers", "2", "--cache", cache,
        "--quiet", "--out", out)
    study = vlab.cost(tiny, levels=3, orders=[1], cells=["hex"], cache=cache, workers=1)
    on_disk = read_json(out / "cost.json")
    assert study.meta["cache_hits"] == len(on_disk["runs"])  # the CLI's runs, not recomputed
    assert steady(study.data) == steady(on_disk)
    assert study.recommendation == on_disk["recommendation"] and study.recommended == on_disk["recommended"]
    with open(out / "cost.csv", newline="", encoding="utf-8") as fh:
        headers = next(csv.reader(fh))
    frame = study.to_pandas()
    assert isinstance(frame, pd.DataFrame) and list(frame.columns) == headers == study.headers
    assert len(frame) == len(on_disk["runs"])


def test_cost_names_a_bad_option(tiny):
    with pytest.raises(vlab.SceneError, match=r"target 2: a relative accuracy in \(0, 1\)"):
        vlab.cost(tiny, target=2)
    with pytest.raises(vlab.SceneError, match="cells 'wedge'.*tet,hex,gmsh-tet"):
        vlab.cost(tiny, cells=["wedge"])
    with pytest.raises(vlab.SceneError, match="gmsh-tet meshes a dogbone; .*tiny.toml has specimen.shape = 'block'"):
        vlab.cost(tiny, cells=["gmsh-tet"])


def test_sweep_names_a_malformed_grid(tiny):
    with pytest.raises(vlab.SceneError, match="expected section.key=value1,value2"):
        vlab.sweep(tiny, ["material.nu"])


CASES = ("invalid-meshes-refused", "inversion-stop")


def test_stability_has_the_verdicts_of_results_json(tmp_path):
    pytest.importorskip("pandas")
    out = tmp_path / "stability"
    cli("stability", *(a for c in CASES for a in ("--case", c)), "--no-render", "--quiet", "--out", out)
    suite = vlab.stability(cases=CASES)
    on_disk = read_json(out / "results.json")
    assert steady(suite.data) == steady(on_disk)
    assert suite.verdicts == {c["name"]: c["passed"] for c in on_disk["cases"]} == dict.fromkeys(CASES, True)
    assert list(suite.to_pandas()["name"]) == list(CASES)
    with pytest.raises(vlab.SceneError, match="unknown stability case.*nope; known: "):
        vlab.stability(cases=["nope"])


def test_to_pandas_without_pandas_says_how_to_install_it(monkeypatch):
    result = vlab.Scene.from_dict({"name": "api-np", "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
                                   "mesh": {"size": 10.0, "cell": "hex"},
                                   "material": {"model": "linear", "E": 10.0, "nu": 0.3},
                                   "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.01,
                                            "steps": 2}}).run()
    monkeypatch.setitem(sys.modules, "pandas", None)  # as if it were not installed
    with pytest.raises(ImportError, match="optional dependency of vlab: pip install pandas"):
        result.curve.to_pandas()
    monkeypatch.undo()
    pd = pytest.importorskip("pandas")
    table = result.curve.to_pandas()
    assert isinstance(table, pd.DataFrame) and list(table["strain"]) == list(result.curve["strain"])


def test_the_commands_are_names_of_vlab_and_the_modules_stay_modules():
    import vlab.compare as compare_module
    import vlab.export as export_module

    for name in ("fit", "compare", "sweep", "cost", "stability", "export"):
        assert callable(getattr(vlab, name)), name
    assert vlab.compare is compare_module and compare_module.compare_models  # the module, callable
    assert vlab.export is export_module and "abaqus" in export_module.EXPORTERS
