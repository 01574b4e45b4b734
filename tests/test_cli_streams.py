"""The CLI's two streams, as a shell expects: results on stdout, progress, warnings and errors on
stderr, so ``vlab run … > out.txt`` keeps the results; and messages printed verbatim on both
(``vlab info``'s install hint keeps its ``[cad]``)."""

import os
import subprocess
import sys
from pathlib import Path

from typer.testing import CliRunner

from vlab.cli import app

ROOT = Path(__file__).resolve().parents[1]
SPECIMENS = ROOT / "specimens"


def small_load_unload(tmp_path: Path) -> Path:
    """The plasticity load–unload block on one element per side, 3 steps (a warning: Hencky)."""
    text = (SPECIMENS / "block-plasticity-load-unload.toml").read_text(encoding="utf-8")
    path = tmp_path / "small.toml"
    path.write_text(text.replace("size = 5.0", "size = 10.0").replace("steps = 20", "steps = 3"), encoding="utf-8")
    return path


def test_run_prints_results_on_stdout_and_progress_and_warnings_on_stderr(tmp_path):
    env = os.environ | {"PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-m", "vlab", "run", str(small_load_unload(tmp_path)), "--no-render",
                           "--no-estimate", "-o", str(tmp_path / "r")], capture_output=True, text=True,
                          timeout=300, env=env, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    out, err = proc.stdout, proc.stderr
    assert out.startswith("completed in"), out  # the summary, the measured constants, the report's place
    assert "measured E" in out and f"report: {tmp_path / 'r' / 'index.html'}" in out, out
    assert "the elastic part is Hencky" in err and "Newton" in err, err  # the warning and the progress
    for line in out.splitlines():
        assert "Hencky" not in line and "Newton (" not in line and "load levels" not in line, out
    assert "completed in" not in err and "measured E" not in err and "report:" not in err, err


def test_an_invalid_scene_says_why_on_stderr_and_nothing_on_stdout(tmp_path):
    bad = small_load_unload(tmp_path)
    bad.write_text(bad.read_text(encoding="utf-8").replace("nu = 0.33", "nu = 0.7"), encoding="utf-8")
    proc = subprocess.run([sys.executable, "-m", "vlab", "run", str(bad), "-o", str(tmp_path / "r")],
                          capture_output=True, text=True, timeout=300,
                          env=os.environ | {"PYTHONPATH": str(ROOT)}, cwd=tmp_path)
    assert proc.returncode == 2 and proc.stdout == "" and "material.nu" in proc.stderr, (proc.stdout, proc.stderr)


def test_info_keeps_the_cad_extra_in_its_install_hint(monkeypatch):
    import vlab.geometry.cad

    monkeypatch.setattr(vlab.geometry.cad, "gmsh_version", lambda: None)  # as on a machine without gmsh
    result = CliRunner().invoke(app, ["info"])
    assert result.exit_code == 0, result.output
    assert 'pip install "vlab[cad]"' in result.stdout, result.stdout


def test_info_prints_solver_hints_with_brackets_verbatim(monkeypatch):
    import vlab.fe.iterative

    monkeypatch.setattr(vlab.fe.iterative, "available", lambda: "4.2.3")  # the [solver] note is printed
    result = CliRunner().invoke(app, ["info"])
    assert result.exit_code == 0 and "[solver] linear = 'auto'" in result.stdout, result.stdout
