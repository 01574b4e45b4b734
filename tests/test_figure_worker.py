"""The report's figures drawn by a second process (vlab/report/figure_worker.py): the same PNG bytes
as drawn in process, every failure of the worker raised with its cause and nothing half-written,
no worker process left behind."""

from __future__ import annotations

import json
import os
import sys

import pytest
from typer.testing import CliRunner

from vlab import settings
from vlab.cli import app
from vlab.report.figure_worker import (FigureWorker, FigureWorkerError, draw_figures, figure_job,
                                       running_besides_this, start_figures, wanted)
from vlab.report.outcome import outcome_of
from vlab.report.writer import ReportOptions, write_report
from vlab.run import run_scene
from vlab.scene import parse_scene

OPTIONS = ReportOptions(render=False, vtu=False)


@pytest.fixture(scope="module")
def uniaxial():
    s = parse_scene({"name": "worker", "specimen": {"shape": "block", "size": [4.0, 3.0, 2.0]},
                     "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.45},
                     "test": {"kind": "uniaxial", "stretch": 1.2, "steps": 3}})
    return s, outcome_of(run_scene(s))


def _job(outcome, folder) -> dict:
    return figure_job([outcome.data], False, {}, True) | {"folder": str(folder)}


def test_the_worker_draws_the_same_png_bytes_as_the_process(tmp_path, uniaxial):
    _, outcome = uniaxial
    here, there = tmp_path / "here", tmp_path / "there"
    here.mkdir(), there.mkdir()
    drawn_here = draw_figures(_job(outcome, here))
    with FigureWorker() as worker:
        pending = start_figures(_job(outcome, there), worker)
        assert pending is worker
        drawn_there = pending.result()
    assert drawn_there == drawn_here and [f.file for f in drawn_here] == ["stress_strain.png", "lateral_strain.png"]
    for f in drawn_here:
        assert (here / f.file).read_bytes() == (there / f.file).read_bytes()
    assert worker.proc.returncode == 0


def test_a_report_written_with_a_worker_equals_the_one_written_without(tmp_path, uniaxial):
    s, outcome = uniaxial
    write_report([outcome], tmp_path / "plain", s, None, OPTIONS)
    with FigureWorker() as worker:
        write_report([outcome], tmp_path / "worker", s, None, OPTIONS, worker)
    for name in ("stress_strain.png", "lateral_strain.png"):
        assert (tmp_path / "plain" / name).read_bytes() == (tmp_path / "worker" / name).read_bytes()
    page = (tmp_path / "worker" / "index.html").read_text(encoding="utf-8")
    assert page.count("<figure") == (tmp_path / "plain" / "index.html").read_text(encoding="utf-8").count("<figure")


def test_an_error_in_the_worker_is_raised_with_its_cause_and_no_report_is_left(tmp_path, uniaxial):
    s, outcome = uniaxial
    broken = dict(outcome.data, curve={})  # no curve to draw: the worker's plot raises KeyError
    bad = type(outcome)(outcome.model, broken, outcome.snapshot, outcome.checks)
    with FigureWorker() as worker, pytest.raises(FigureWorkerError, match="KeyError"):
        write_report([bad], tmp_path / "r", s, None, OPTIONS, worker)
    assert not (tmp_path / "r").exists()
    assert [p.name for p in tmp_path.iterdir()] == []  # no staging folder left either


def test_a_worker_killed_before_its_answer_is_a_clear_error(tmp_path, uniaxial):
    _, outcome = uniaxial
    with FigureWorker([sys.executable, "-c", "import os, sys; sys.stdin.read(); os.kill(os.getpid(), 9)"]) as worker:
        pending = start_figures(_job(outcome, tmp_path), worker)
        with pytest.raises(FigureWorkerError, match="exit status -9"):
            pending.result()


def test_a_worker_that_ended_before_its_job_leaves_the_figures_to_the_process(tmp_path, uniaxial, caplog):
    _, outcome = uniaxial
    with FigureWorker([sys.executable, "-c", "import sys; print('no matplotlib here', file=sys.stderr)"]) as worker:
        worker.proc.wait()
        figures = start_figures(_job(outcome, tmp_path), worker).result()
    assert (tmp_path / "lateral_strain.png").exists() and len(figures) == 2
    assert "ended before its job" in caplog.text and "no matplotlib here" in caplog.text


def test_an_unused_worker_exits_at_the_end_of_its_input(tmp_path):
    with FigureWorker() as worker:
        pass
    assert worker.proc.returncode == 0 and list(tmp_path.iterdir()) == []


def test_a_command_that_cannot_start_a_process_draws_in_process(tmp_path, uniaxial, caplog):
    _, outcome = uniaxial
    with FigureWorker([str(tmp_path / "no-such-interpreter")]) as worker:
        assert worker.proc is None and not worker.running()
        figures = start_figures(_job(outcome, tmp_path), worker).result()
    assert len(figures) == 2 and "figures drawn in process" in caplog.text


def test_auto_starts_a_worker_only_where_it_pays(monkeypatch):
    assert wanted("on", cores=1) and not wanted("off", cores=8, others=0)
    monkeypatch.delitem(sys.modules, "matplotlib", raising=False)
    assert wanted("auto", cores=2, others=0) and wanted("auto", cores=2, others=1)
    assert not wanted("auto", cores=1, others=0)  # one core: the worker only competes with the solve
    assert not wanted("auto", cores=2, others=2)  # every core taken by others
    monkeypatch.setitem(sys.modules, "matplotlib", object())
    assert not wanted("auto", cores=8, others=0)  # already imported: drawing here is cheaper


def test_running_tasks_are_read_from_the_kernel():
    n = running_besides_this()
    assert isinstance(n, int) and n >= 0


def test_the_setting_is_validated_naming_the_variable():
    with pytest.raises(ValueError, match="VLAB_FIGURE_PROCESS must be one of auto, on, off"):
        settings.Settings.from_environment({"VLAB_FIGURE_PROCESS": "sometimes"})
    assert settings.Settings.from_environment({"VLAB_FIGURE_PROCESS": "ON"}).figure_process == "on"


def test_vlab_run_with_the_worker_writes_the_report_and_its_figures(tmp_path, monkeypatch):
    scene = tmp_path / "s.toml"
    scene.write_text('name = "w"\n[specimen]\nshape = "block"\nsize = [4.0, 3.0, 2.0]\n[mesh]\nsize = 1.0\n'
                     'cell = "hex"\n[material]\nmodel = "neo-hookean"\nE = 3.0\nnu = 0.45\n'
                     '[test]\nkind = "uniaxial"\nstretch = 1.2\nsteps = 3\n')
    monkeypatch.setenv("VLAB_FIGURE_PROCESS", "on")
    res = CliRunner().invoke(app, ["run", str(scene), "--out", str(tmp_path / "r"), "--no-render",
                                   "--no-estimate", "-q"])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "r" / "lateral_strain.png").stat().st_size > 10_000
    data = json.loads((tmp_path / "r" / "results.json").read_text())
    assert data["converged"] and os.path.exists(tmp_path / "r" / "index.html")


def test_other_output_on_the_workers_stdout_does_not_break_its_answer(tmp_path, uniaxial):
    _, outcome = uniaxial
    noisy = [sys.executable, "-c", "print('a sitecustomize says hello'); import vlab.report.figure_worker as w; "
             "print('{not json'); w.main()"]
    with FigureWorker(noisy) as worker:
        figures = start_figures(_job(outcome, tmp_path), worker).result()
    assert [f.file for f in figures] == ["stress_strain.png", "lateral_strain.png"]
