"""What the terminal shows: a version, -h, one live progress display for `vlab run` (not a line
per level), warnings once each, mesh imports without stray blank lines."""

import re
from pathlib import Path

from typer.testing import CliRunner

from vlab import __version__
from vlab.cli import app

SPECIMENS = Path(__file__).resolve().parents[1] / "specimens"


def test_version_prints_the_package_version():
    result = CliRunner().invoke(app, ["--version"])
    assert result.exit_code == 0 and result.output.strip() == f"vlab {__version__}"


def test_dash_h_is_help():
    result = CliRunner().invoke(app, ["-h"])
    assert result.exit_code == 0 and "Usage" in result.output and "compare" in result.output


def test_run_shows_one_progress_display_and_each_warning_once(tmp_path):
    result = CliRunner().invoke(app, ["run", str(SPECIMENS / "block-plasticity-load-unload.toml"),
                                      "-o", str(tmp_path / "p"), "--no-render"])  # the estimate solves again
    assert result.exit_code == 0, result.output
    assert result.output.count("the elastic part is Hencky") == 1, result.output
    assert re.search(r"\b(\d+)/\1\b", result.output) and "Newton" in result.output, result.output
    assert "level   1" not in result.output and len(result.output.splitlines()) < 16, result.output


def test_quiet_run_prints_only_the_summary(tmp_path):
    result = CliRunner().invoke(app, ["run", "-q", "--no-render", "--no-estimate", "-o", str(tmp_path / "q")])
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[0].startswith("completed in"), result.output


def test_mesh_import_output_starts_without_blank_lines(tmp_path):
    result = CliRunner().invoke(app, ["run", str(SPECIMENS / "mesh-import-bar.toml"), "-q", "--no-render",
                                      "--no-estimate", "-o", str(tmp_path / "m")])
    assert result.exit_code == 0, result.output
    assert result.output.startswith("completed in"), repr(result.output[:80])
