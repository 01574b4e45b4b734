import csv
import html
import json
import re
from html.parser import HTMLParser

import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.report.html import _fmt
from vlab.report.writer import ReportOptions, write_report

from conftest import ALL_MODELS


class _Sources(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links = [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs["src"])
        if tag == "a":
            self.links.append(attrs["href"])


def _sources(page: str) -> _Sources:
    parser = _Sources()
    parser.feed(page)
    return parser


def test_html_has_every_models_measured_numbers(comparison):
    page = (comparison.folder / "index.html").read_text(encoding="utf-8")
    for out in comparison.outcomes:
        m = out.data["measured"]
        assert f"<th>{out.model}</th>" in page
        for value in (m["E"], m["nu"], out.data["curve"]["force"][-1], out.data["timing"]["total_s"]):
            assert _fmt(value) in page or _fmt(value, 3) in page, (out.model, value)
        solver = out.data["solver"]
        assert (f"<td class=num>{sum(solver['newton_iterations'])} ({sum(solver['exact_iterations'])} refactorized; "
                f"{solver['factorizations']} factorizations in all") in page
    assert "Measured ν = " in page and "spring-network" in page
    assert comparison.scene.content_hash() in page
    assert html.escape('name = "block-neo-hookean"') in page  # the scene file as run


def test_every_referenced_file_exists(comparison):
    sources = _sources((comparison.folder / "index.html").read_text(encoding="utf-8"))
    assert len(sources.images) >= 4  # overlay, lateral, render, animation
    for ref in sources.images + sources.links:
        assert (comparison.folder / ref).is_file(), ref


def test_model_files_results_and_curves(comparison):
    for model in ALL_MODELS:
        data = json.loads((comparison.folder / model / "results.json").read_text())
        assert data["input"]["model"] == model
        with open(comparison.folder / model / "curve.csv") as fh:
            rows = list(csv.DictReader(fh))
        assert len(rows) == len(data["curve"]["stress"])
        assert float(rows[-1]["stress"]) == pytest.approx(data["curve"]["stress"][-1])


def test_departures_from_neo_hookean(comparison):
    dep = comparison.summary["departures_from_neo_hookean"]
    assert "neo-hookean" not in dep
    # StVK stiffens, linear stays straight: StVK parts from Neo-Hookean first, both within the test
    assert 0 < dep["stvk"]["5%"] < dep["stvk"]["10%"] < 0.5
    assert 0 < dep["linear"]["5%"] < dep["linear"]["10%"] < 0.5
    assert dep["stvk"]["5%"] < dep["linear"]["5%"]
    # the crossing lies between the two recorded levels whose stress ratio brackets 5 %
    nh, st = comparison.by_model["neo-hookean"].data["curve"], comparison.by_model["stvk"].data["curve"]
    rel = [abs(a - b) / b for a, b in zip(st["stress"], nh["stress"])]
    i = next(k for k, r in enumerate(rel) if r >= 0.05)
    assert rel[i - 1] < 0.05 and st["strain"][i - 1] < dep["stvk"]["5%"] <= st["strain"][i]


def test_progress_reports_every_level_of_every_model(comparison):
    for model in ALL_MODELS:
        done = [e for e in comparison.events if e[0] == model]
        assert done[-1][1] == done[-1][2] == len(comparison.by_model[model].data["curve"]["stress"])


def test_single_file_inlines_every_image(comparison, tmp_path):
    out = tmp_path / "one"
    write_report(comparison.outcomes[:2], out, comparison.scene, None,
                 ReportOptions(single_file=True, render=False, vtu=False))
    sources = _sources((out / "index.html").read_text(encoding="utf-8"))
    assert sources.images and all(s.startswith("data:image/png;base64,") for s in sources.images)


def test_failed_report_leaves_nothing_behind(comparison, tmp_path):
    out = tmp_path / "never"
    with pytest.raises(ValueError, match="gif model 'stvk-volumetric'"):
        write_report(comparison.outcomes, out, comparison.scene, None, ReportOptions(gif_model="stvk-volumetric"))
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_cli_run_writes_a_one_model_report(tmp_path):
    result = CliRunner().invoke(app, ["run", "--out", str(tmp_path / "r"), "-q", "--no-render", "--true"])
    assert result.exit_code == 0, result.output
    for name in ("index.html", "results.json", "curve.csv", "stress_strain.png", "lateral_strain.png",
                 "scene.toml", "neo-hookean.pvd"):
        assert (tmp_path / "r" / name).is_file(), name


def test_cli_compare_rejects_bad_models_and_gif(tmp_path):
    bad = CliRunner().invoke(app, ["compare", "--models", "linear,mooney", "-o", str(tmp_path / "x")])
    assert bad.exit_code == 2 and "mooney" in bad.output and "spring-network" in bad.output
    gif = CliRunner().invoke(app, ["compare", "--models", "linear", "--gif", "stvk", "-o", str(tmp_path / "x")])
    assert gif.exit_code == 2 and "--gif" in gif.output
    assert not (tmp_path / "x").exists()


def test_cli_compare_quiet_two_models(tmp_path):
    result = CliRunner().invoke(app, ["compare", "--models", "linear,neo-hookean", "-q", "--no-render",
                                      "--field", "J", "-o", str(tmp_path / "c")])
    assert result.exit_code == 0, result.output
    assert re.fullmatch(r"report: \S+index.html\s*", result.output), result.output  # nothing but the path
    assert (tmp_path / "c" / "linear" / "results.json").is_file()


def test_compare_writes_its_own_folder_beside_the_run_report(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ran = CliRunner().invoke(app, ["run", "-q", "--no-render", "--no-estimate"])
    assert ran.exit_code == 0, ran.output
    before = (tmp_path / "reports" / "block-neo-hookean" / "results.json").read_bytes()
    compared = CliRunner().invoke(app, ["compare", "--models", "linear", "-q", "--no-render", "-j", "1"])
    assert compared.exit_code == 0, compared.output
    assert (tmp_path / "reports" / "block-neo-hookean-compare" / "comparison.json").is_file()
    assert (tmp_path / "reports" / "block-neo-hookean" / "results.json").read_bytes() == before
