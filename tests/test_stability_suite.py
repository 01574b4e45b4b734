"""`vlab stability`: the registry of hard cases, the fast subset end to end, and the full suite (slow)."""

import json

import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.verification import suite
from vlab.verification.suite import CaseContext, Outcome, register, run_suite, select


@pytest.fixture(scope="module")
def fast_report(stability_fast_report):
    return stability_fast_report  # run once per session (conftest), shared with the screenshot test


def test_the_fast_subset_passes_and_writes_table_json_and_html(fast_report):
    result, out = fast_report
    assert result.exit_code == 0, result.output
    data = json.loads((out / "results.json").read_text())
    names = {c["name"] for c in data["cases"]}
    assert {"stvk-compression-limit-point", "stvk-tension-refused", "inversion-stop", "missing-grip-under-constrained",
            "invalid-meshes-refused", "buckling-clamped-strip-L10", "cook-membrane-0.4999-coarse",
            "nu-0.5-refused", "dogbone-1ba-nu-0.499-mixed"} <= names
    assert data["failed"] == 0 and data["passed"] == len(data["cases"]) == len(select(fast_only=True))
    assert all(c["fast"] for c in data["cases"])
    for column in ("case", "expected", "got", "converged", "iterations", "cutbacks", "neg. eig.", "time", "result"):
        assert column in result.output
    page = (out / "index.html").read_text()
    assert "Clamped strip buckling against Euler" in page and "FAIL" not in page
    strip = next(c for c in data["cases"] if c["name"] == "buckling-clamped-strip-L10")
    assert strip["negative_eigenvalues"] == 1 and 0 < strip["details"]["relative_difference"] < 0.12
    for figure in strip["figures"]:
        assert (out / figure).stat().st_size > 10_000


def test_the_fast_subset_shows_locking_its_cure_and_the_nu_half_refusal(fast_report):
    _, out = fast_report
    cases = {c["name"]: c for c in json.loads((out / "results.json").read_text())["cases"]}
    runs = cases["cook-membrane-0.4999-coarse"]["details"]["runs"]
    ratio = {(r["element"], r["divisions"]): r["ratio_to_reference"] for r in runs}
    assert ratio[("Q1", 4)] < 0.45 < 0.8 < ratio[("Q1/P0", 4)] and abs(ratio[("Q2/P1dc", 2)] - 1) < 0.02
    messages = cases["nu-0.5-refused"]["details"]["messages"]
    assert len(messages) == 3 and all("0.4999" in m and "mixed" in m for m in messages)
    errors = cases["dogbone-1ba-nu-0.499-mixed"]["details"]["relative_errors"]
    assert abs(errors["mixed"]["nu"]) < 0.01 < errors["displacement"]["nu"]


def test_cases_register_once_and_a_raising_case_fails_with_its_message(monkeypatch):
    monkeypatch.setattr(suite, "CASES", dict(suite.CASES))

    @register("always-ok", "passes")
    def ok(context):
        return Outcome("fine", True, True, iterations=3)

    @register("broken", "raises")
    def broken(context):
        raise ZeroDivisionError("a bug in the case")

    with pytest.raises(ValueError, match="registered twice"):
        register("always-ok", "again")(ok)
    results = run_suite(select(names=["always-ok", "broken"]), CaseContext())
    assert [r.passed for r in results] == [True, False]
    assert "ZeroDivisionError: a bug in the case" in results[1].outcome.got and results[1].seconds >= 0
    with pytest.raises(KeyError, match="unknown stability case"):
        select(names=["no-such-case"])


def test_cli_refuses_contradictory_or_unknown_selections(tmp_path):
    runner = CliRunner()
    assert runner.invoke(app, ["stability", "--fast", "--all", "--out", str(tmp_path)]).exit_code == 2
    result = runner.invoke(app, ["stability", "--case", "nope", "--out", str(tmp_path)])
    assert result.exit_code == 2 and "unknown stability case" in result.output


@pytest.mark.slow
def test_the_full_suite_passes(tmp_path):
    results = run_suite(select(), CaseContext(tmp_path, render=False))
    assert [r.name for r in results if not r.passed] == []
