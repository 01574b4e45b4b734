"""Shared fixtures: one four-model comparison of the built-in block scene, run once per session."""

from __future__ import annotations

import sys
from pathlib import Path

from types import SimpleNamespace

import pytest

sys.path.insert(0, str(Path(__file__).parent))  # tests/scenes.py helpers

ALL_MODELS = ("linear", "stvk", "neo-hookean", "spring-network")


@pytest.fixture(scope="session")
def comparison(tmp_path_factory):
    from vlab.cli import default_scene_path
    from vlab.compare import compare_models
    from vlab.report.writer import ReportOptions, write_report
    from vlab.scene import load_scene

    path = default_scene_path()
    scene = load_scene(path)
    events = []
    outcomes = compare_models(scene, ALL_MODELS, workers=2, progress=lambda *e: events.append(e))
    folder = tmp_path_factory.mktemp("report") / scene.name
    summary = write_report(outcomes, folder, scene, path.read_text(encoding="utf-8"),
                           ReportOptions(gif_model="neo-hookean"))
    return SimpleNamespace(scene=scene, outcomes=outcomes, folder=folder, summary=summary, events=events,
                           by_model={o.model: o for o in outcomes})


@pytest.fixture(scope="session")
def stability_fast_report(tmp_path_factory):
    """`vlab stability --fast` once per session: (CLI result, report folder)."""
    from typer.testing import CliRunner

    from vlab.cli import app

    out = tmp_path_factory.mktemp("stability") / "report"
    result = CliRunner().invoke(app, ["stability", "--fast", "--out", str(out), "--quiet"])
    return result, out
