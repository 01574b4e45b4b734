"""Streams of the commands besides `vlab run` (tests/test_cli_streams.py has run's and info's), as a
shell sees them (``vlab fit … > out.txt`` keeps the results): summaries, tables and the report's
path on stdout; progress, warnings and errors on stderr."""

from __future__ import annotations

import json
import re

import numpy as np
from typer.testing import CliRunner

from vlab.cli import app
from vlab.dic import speckle
from vlab.dic.images import write_grey
from vlab.identify.card import card_toml


def _invoke(*args):
    res = CliRunner().invoke(app, [str(a) for a in args])
    return res, " ".join(res.stdout.split()), " ".join(res.stderr.split())


def _uniaxial_fit(tmp_path, model="neo-hookean"):
    """A Neo-Hookean uniaxial nominal-stress curve P = 2 C10 (λ − λ⁻²), C10 = 0.3 MPa."""
    lam = np.linspace(1.0, 3.0, 12)
    (tmp_path / "u.csv").write_text("lambda,P\n" + "".join(f"{float(a)!r},{float(0.6 * (a - a ** -2))!r}\n" for a in lam))
    f = tmp_path / "fit.toml"
    f.write_text(f'name = "s"\n[model]\nname = "{model}"\n[[data]]\nfile = "u.csv"\nkind = "uniaxial"\n'
                 'columns = { stretch = "lambda", stress = "P" }\n[options]\nstarts = 2\n')
    return f


def test_fit_summary_and_report_path_on_stdout_errors_on_stderr(tmp_path):
    res, out, err = _invoke("fit", _uniaxial_fit(tmp_path), "--out", tmp_path / "o")
    assert res.exit_code == 0, res.output
    assert re.search(r"mu = 0\.6\d* ±", out) and "rms" in out and f"report: {tmp_path / 'o'}" in out, out
    assert "mu =" not in err and "report:" not in err, err
    bad, out, err = _invoke("fit", tmp_path / "missing.toml", "--out", tmp_path / "p")
    assert bad.exit_code == 2 and "invalid fit file" in err and out == ""


def test_fit_ranking_on_stdout(tmp_path):
    res, out, err = _invoke("fit", _uniaxial_fit(tmp_path), "--models", "neo-hookean,yeoh", "--out", tmp_path / "o")
    assert res.exit_code in (0, 3), res.output
    assert "1. " in out and "2. " in out and "held-out rms" in out and "report:" in out, out
    assert "held-out rms" not in err


def test_fit_warnings_on_stderr_verdict_on_stdout(tmp_path):
    """Mooney–Rivlin on a curve it cannot follow stably (C01 < 0): the verdict (exit 3) is a result,
    the fit's own warnings are warnings."""
    (tmp_path / "u.csv").write_text("lambda,P\n1.0,0\n1.5,0.3\n2.0,0.5\n2.5,0.7\n3.0,0.9\n")
    f = tmp_path / "fit.toml"
    f.write_text('name = "t"\n[model]\nname = "mooney-rivlin"\n[[data]]\nfile = "u.csv"\nkind = "uniaxial"\n'
                 'columns = { stretch = "lambda", stress = "P" }\n')
    res, out, err = _invoke("fit", f, "--out", tmp_path / "o")
    assert res.exit_code == 3 and "card not trustworthy" in out and "card not trustworthy" not in err
    assert "warning the fitted model is not Drucker-stable" in err and "not Drucker-stable over the whole" not in out, (out, err)


def test_design_verdicts_on_stdout_errors_on_stderr(tmp_path):
    f = _uniaxial_fit(tmp_path)
    res, out, err = _invoke("design", f, "--out", tmp_path / "o", "--noise", "0.01", "--candidates", "uniaxial,planar", "--combine", "2")
    assert res.exit_code == 0, res.output
    assert "next:" in out and "present data" in out and "report:" in out and "next:" not in err, (out, err)
    bad, out, err = _invoke("design", f, "--out", tmp_path / "p", "--points", "2")
    assert bad.exit_code == 2 and "--points 2" in err and out == ""


def test_export_and_import_card_files_on_stdout_refusals_on_stderr(tmp_path):
    src = tmp_path / "card.toml"
    src.write_text(card_toml({"model": "yeoh", "C10": 0.28, "C20": -0.0123, "C30": 0.00041, "K": 88.1}))
    res, out, err = _invoke("export", src, "--to", "abaqus", "--out", tmp_path / "a.inp")
    assert res.exit_code == 0 and out == f"abaqus: {tmp_path / 'a.inp'}" and err == "", (out, err)
    back, out, err = _invoke("import-card", tmp_path / "a.inp", "--out", tmp_path / "b.toml")
    assert back.exit_code == 0 and f"card: {tmp_path / 'b.toml'}" in out and "C30" in out and err == "", (out, err)
    bad, out, err = _invoke("export", src, "--to", "nastran", "--out", tmp_path / "n.bdf")
    assert bad.exit_code == 2 and "cannot export" in err and out == ""
    nh = tmp_path / "nh.toml"
    nh.write_text(card_toml({"model": "neo-hookean", "E": 10.0, "nu": 0.3}))
    refused, out, err = _invoke("export", nh, "--to", "lsdyna", "--out", tmp_path / "nh.k")
    assert refused.exit_code == 2 and out == "" and not (tmp_path / "nh.k").exists()
    assert err.count("cannot export") == 1 and "lsdyna" in err, err  # the refusal's words, the label not twice


def test_dic_report_path_on_stdout_progress_on_stderr(tmp_path):
    shape = (96, 112)
    pattern = speckle.make_pattern(shape, size=4.0, density=0.5, seed=5)
    write_grey(tmp_path / "ref.tif", speckle.render(pattern, shape, supersample=2), 16)
    write_grey(tmp_path / "a.tif", speckle.render(pattern, shape, speckle.translation(0.4, 0.2), supersample=2), 16)
    res, out, err = _invoke("dic", tmp_path / "ref.tif", tmp_path / "a.tif", "--out", tmp_path / "d")
    assert res.exit_code == 0, res.output
    assert out == f"report: {tmp_path / 'd' / 'index.html'}" and "subsets converged" in err, (out, err)
    bad, out, err = _invoke("dic", tmp_path / "ref.tif", tmp_path / "a.tif", "--subset", "30", "--out", tmp_path / "e")
    assert bad.exit_code == 2 and "--subset" in err and out == ""


def test_budget_results_on_stdout_progress_on_stderr(tmp_path):
    """Two samples of a one-element block on a one-worker Dask cluster (the slow test of
    tests/test_uncertainty_budget.py runs a real budget)."""
    (tmp_path / "s.toml").write_text(
        'name = "b"\n[specimen]\nshape = "block"\nsize = [10.0, 10.0, 10.0]\n[mesh]\nsize = 10.0\ncell = "hex"\n'
        '[material]\nmodel = "neo-hookean"\nE = 10.0\nnu = 0.3\n[test]\nkind = "uniaxial"\ngrips = "roller"\n'
        'stretch = 1.003\nsteps = 2\n[uncertainty]\nsamples = 2\nwidth = 0.1\nload_cell_class = 1\n'
        'resolution = false\n')
    res, out, err = _invoke("budget", tmp_path / "s.toml", "--out", tmp_path / "o", "--cache", tmp_path / "c", "-j", "1")
    assert res.exit_code == 0, res.output
    assert re.search(r"E = 10\.0\d* ± ", out) and "report:" in out, out
    assert "done" in err and "E = " not in err, err  # the sweeps' progress bars
    data = json.loads((tmp_path / "o" / "budget.json").read_text())
    assert f"{data['E']['mean']:.6g}" in out
    bad, out, err = _invoke("budget", tmp_path / "s.toml", "--samples", "0", "--out", tmp_path / "p",
                            "--cache", tmp_path / "c")
    assert bad.exit_code == 2 and "--samples 0" in err and out == ""
