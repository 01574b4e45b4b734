"""The command's process: fast exit after the CLI (vlab/__main__.py). (Its figures' process:
tests/test_figure_worker.py.)"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

import vlab.__main__ as entry


def _main(monkeypatch, argv):
    """The entry point in this process, its final exit replaced by a record of the code."""
    codes = []
    monkeypatch.setattr(sys, "argv", ["vlab", *argv])
    monkeypatch.setattr(entry, "_finish", codes.append)
    entry.main()
    return codes


def test_the_entry_point_ends_the_process_with_the_commands_exit_code(monkeypatch, capsys):
    assert _main(monkeypatch, ["moduli", "--E", "10", "--nu", "0.3"]) == [0]
    assert "lambda" in capsys.readouterr().out.lower()
    assert _main(monkeypatch, ["run", "/nonexistent/scene.toml"]) == [2]


def test_the_fast_exit_joins_threads_runs_atexit_handlers_and_flushes_first():
    script = textwrap.dedent("""
        import atexit, sys, threading, time
        atexit.register(lambda: print("atexit ran"))
        threading.Thread(target=lambda: (time.sleep(0.3), print("thread finished"))).start()
        sys.argv = ["vlab", "moduli", "--E", "10", "--nu", "0.3"]
        import vlab.__main__
        vlab.__main__.main()
        print("not reached")
    """)
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert proc.returncode == 0
    assert "thread finished" in proc.stdout and proc.stdout.rstrip().endswith("atexit ran")
    assert "not reached" not in proc.stdout


@pytest.mark.parametrize("argv, code, text", [(["--version"], 0, "vlab "), (["run", "/nonexistent/x.toml"], 2, "x.toml")])
def test_python_m_vlab_keeps_its_exit_codes_and_output(argv, code, text):
    proc = subprocess.run([sys.executable, "-m", "vlab", *argv], capture_output=True, text=True)
    assert proc.returncode == code
    assert text in proc.stdout + proc.stderr
