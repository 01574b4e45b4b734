"""Faults while a report is written (#30): a full disk (ENOSPC) in this process, in the figure
worker and in the manifest; a read-only ``--out``; two runs writing the same ``--out`` at once; a
report folder deleted mid-run. Each ends with exit 2 and a message naming the folder and the cause
(docs/reference/errors-and-files.md), no traceback, the folder it was to replace as it was, and no
partial report with a manifest (vlab.report.folder)."""

from __future__ import annotations

import errno
import json
import multiprocessing
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.report.folder import MANIFEST, ReportFolderError, report_folder
from helpers_scenes import block_toml

runner = CliRunner()
ROOT = Path(__file__).resolve().parents[1]
SCENE = block_toml("fault-block")
FAST = ["--no-render", "--no-estimate", "-q"]


@pytest.fixture
def lab(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.toml").write_text(SCENE)
    return tmp_path


def _run(*args):
    return runner.invoke(app, ["run", "scene.toml", *args, *FAST])


def _snapshot(folder: Path) -> dict:
    """Every file below ``folder`` with its bytes (what must survive a failed replacement)."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def _siblings(parent: Path) -> list[str]:
    return [p.name for p in parent.iterdir() if ".vlab-" in p.name]


def _clean_failure(result, *words):
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output, result.output
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    for word in words:
        assert word in result.output, result.output


def _is_whole_report(folder: Path) -> bool:
    """A manifest listing exactly the files there, and a results.json that parses."""
    manifest = json.loads((folder / MANIFEST).read_text())
    files = {str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file()} - {MANIFEST}
    json.loads((folder / "results.json").read_text())
    return set(manifest["files"]) == files


# --- disk full -------------------------------------------------------------------------------

def _enospc(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


@pytest.mark.parametrize("where", ["page", "manifest"])
def test_a_full_disk_leaves_the_previous_report_as_it_was_and_says_free_space(lab, monkeypatch, where):
    import vlab.report.folder as folder
    import vlab.report.html as html

    assert _run("--out", "out").exit_code == 0
    before = _snapshot(lab / "out")
    monkeypatch.setattr(*((html, "write_comparison", _enospc) if where == "page" else
                          (folder, "_write_manifest", _enospc)))
    result = _run("--out", "out")
    _clean_failure(result, "'out'", "No space left on device", "free space", "nothing was written")
    assert _snapshot(lab / "out") == before and not _siblings(lab)


@pytest.fixture
def small_disk(tmp_path):
    """A 20 MiB tmpfs (needs root and CAP_SYS_ADMIN; skipped with the reason elsewhere)."""
    point = tmp_path / "disk"
    point.mkdir()
    if os.geteuid() != 0 or not shutil.which("mount") or subprocess.run(
            ["mount", "-t", "tmpfs", "-o", "size=20m", "tmpfs", str(point)], capture_output=True).returncode:
        pytest.skip("mounting a tmpfs needs root (with CAP_SYS_ADMIN)")
    try:
        yield point
    finally:
        subprocess.run(["umount", "-l", str(point)], capture_output=True)


def _vlab(*args, cwd: Path, **env) -> subprocess.CompletedProcess:
    environ = dict(os.environ, PYTHONPATH=str(ROOT), **env)
    return subprocess.run([sys.executable, "-m", "vlab", *args], cwd=cwd, env=environ, capture_output=True,
                          text=True, timeout=300)


def test_a_really_full_disk_in_the_figure_worker_is_exit_2_without_its_traceback(lab, small_disk):
    """The figure worker (a second process) writes the PNGs: its ENOSPC was rc 1 and printed the
    worker's traceback; now it is the same exit 2 as the writer's own OS errors."""
    out = small_disk / "out"
    first = _vlab("run", "scene.toml", "--out", str(out), *FAST, cwd=lab)
    assert first.returncode == 0, first.stderr
    before = _snapshot(out)
    room = os.statvfs(small_disk)
    filler = (room.f_bavail * room.f_frsize) - 120 * 1024  # the page and CSVs fit, the PNGs do not
    (small_disk / "filler").write_bytes(b"\0" * filler)
    second = _vlab("run", "scene.toml", "--out", str(out), *FAST, cwd=lab, VLAB_FIGURE_PROCESS="on")
    text = second.stdout + second.stderr
    assert second.returncode == 2, text
    assert "No space left on device" in text and "Traceback" not in text, text
    assert _snapshot(out) == before and sorted(p.name for p in small_disk.iterdir()) == ["filler", "out"]


def test_an_os_error_in_the_figure_worker_comes_back_as_that_os_error(lab):
    from vlab.report.figure_worker import FigureWorker, figure_job

    assert _run("--out", "out").exit_code == 0
    data = json.loads((lab / "out" / "results.json").read_text())
    with FigureWorker() as worker:
        worker.submit(figure_job([data], False, {}, True) | {"folder": str(lab / "removed")})
        with pytest.raises(OSError) as caught:
            worker.result()
    assert caught.value.errno == errno.ENOENT


# --- read-only --out -------------------------------------------------------------------------

@pytest.fixture
def read_only(lab):
    """Make a folder read-only for this process: a read-only bind mount as root (chmod does not stop
    root), chmod otherwise; skipped with the reason where neither is possible."""
    mounted = []

    def make(folder: Path):
        if os.geteuid() != 0:
            for path in [folder, *[p for p in folder.rglob("*") if p.is_dir()]]:
                path.chmod(0o555)
            return
        if not shutil.which("mount") or subprocess.run(["mount", "--bind", str(folder), str(folder)],
                                                       capture_output=True).returncode:
            pytest.skip("running as root, where chmod does not stop writes, and no bind mount is allowed")
        mounted.append(folder)
        subprocess.run(["mount", "-o", "remount,ro,bind", str(folder)], check=True)

    yield make
    for folder in mounted:
        subprocess.run(["umount", "-l", str(folder)], capture_output=True)
    for path in lab.rglob("*"):
        if path.is_dir():
            path.chmod(0o755)


def test_a_read_only_out_is_refused_before_any_work_and_left_as_it_was(lab, read_only):
    assert _run("--out", "out").exit_code == 0
    before = _snapshot(lab / "out")
    read_only(lab / "out")
    result = _run("--out", "out")
    _clean_failure(result, "'out'", "read-only")
    assert _snapshot(lab / "out") == before and not _siblings(lab)


def test_a_read_only_folder_inside_out_is_refused_naming_it(lab, monkeypatch):
    """Where the test cannot make a real read-only folder (root), os.access answers as for one."""
    import vlab.report.folder as folder

    assert _run("--out", "out").exit_code == 0
    before = _snapshot(lab / "out")
    vtu = str(lab / "out" / "vtu")
    real = os.access
    monkeypatch.setattr(folder.os, "access", lambda path, mode, **kw: str(path) != vtu and real(path, mode, **kw))
    result = _run("--out", "out")
    _clean_failure(result, "read-only", "'vtu'")
    assert _snapshot(lab / "out") == before


# --- two runs at once ------------------------------------------------------------------------

def test_a_run_whose_out_another_live_vlab_is_writing_is_refused_naming_it(lab):
    from vlab.report.folder import _HOST, MARKER

    assert _run("--out", "out").exit_code == 0
    before = _snapshot(lab / "out")
    other = os.getppid()  # a live process: the other writer
    busy = lab / f".out.vlab-tmp-{_HOST}-{other}-0123abcd"
    busy.mkdir()
    (busy / MARKER).write_text("{}")
    result = _run("--out", "out")
    _clean_failure(result, "another vlab process", f"pid {other}", "nothing was written")
    assert _snapshot(lab / "out") == before and busy.is_dir()


def _writer(target: str, ident: int, start, results) -> None:
    """One process writing a three-file report into ``target`` as soon as ``start`` is set."""
    start.wait()
    try:
        with report_folder(Path(target), "race") as tmp:
            for name in ("results.json", "a.txt", "b.txt"):
                (tmp / name).write_text(json.dumps({"writer": ident}))
        results.put((ident, "written"))
    except ReportFolderError as exc:
        results.put((ident, str(exc)))


def test_processes_racing_for_one_out_end_with_one_whole_report_or_a_clear_refusal(tmp_path):
    ctx = multiprocessing.get_context("fork")
    target = tmp_path / "out"
    for _ in range(5):
        start, results = ctx.Event(), ctx.Queue()
        procs = [ctx.Process(target=_writer, args=(str(target), i, start, results)) for i in range(4)]
        for p in procs:
            p.start()
        start.set()
        answers = dict(results.get(timeout=60) for _ in procs)
        for p in procs:
            p.join(60)
        assert "written" in answers.values(), answers
        refused = [a for a in answers.values() if a != "written"]
        assert all("another vlab process" in a for a in refused), refused
        writers = {json.loads((target / n).read_text())["writer"] for n in ("results.json", "a.txt", "b.txt")}
        assert len(writers) == 1 and answers[writers.pop()] == "written"  # never a mixture
        assert _is_whole_report(target) and not _siblings(tmp_path)


def test_two_vlab_runs_at_once_on_one_out_both_end_clearly_and_leave_one_whole_report(lab):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    procs = [subprocess.Popen([sys.executable, "-m", "vlab", "run", "scene.toml", "--out", "out", *FAST],
                              cwd=lab, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
             for _ in range(2)]
    outputs = [(p.wait(300), p.stdout.read()) for p in procs]
    assert all(rc in (0, 2) and "Traceback" not in text for rc, text in outputs), outputs
    assert any(rc == 0 for rc, _ in outputs), outputs
    assert all("another vlab process" in text for rc, text in outputs if rc == 2), outputs
    assert _is_whole_report(lab / "out") and not _siblings(lab)


# --- a report folder deleted mid-run ---------------------------------------------------------

def _delete_during_vtu(monkeypatch, victim):
    """Remove ``victim(tmp)`` when the VTU files are about to be written (mid-report)."""
    import vlab.post.vtu as vtu

    real = vtu.write_time_series

    def deleting(snapshot, folder, stem):
        shutil.rmtree(victim(Path(folder)))
        return real(snapshot, folder, stem)

    monkeypatch.setattr(vtu, "write_time_series", deleting)


def test_the_folder_being_written_deleted_mid_run_is_an_error_not_a_partial_report(lab, monkeypatch):
    """The VTU writer's mkdir(parents=True) would make the deleted folder again: the rest of the
    report would have been written into it (no marker) and renamed into place."""
    assert _run("--out", "out").exit_code == 0
    before = _snapshot(lab / "out")
    _delete_during_vtu(monkeypatch, lambda tmp: tmp)
    result = _run("--out", "out")
    _clean_failure(result, "'out'", "removed", "nothing was written")
    assert _snapshot(lab / "out") == before and not _siblings(lab)


def test_the_report_folder_deleted_mid_run_is_written_whole_again(lab, monkeypatch):
    assert _run("--out", "out").exit_code == 0
    _delete_during_vtu(monkeypatch, lambda tmp: lab / "out")
    result = _run("--out", "out")
    assert result.exit_code == 0, result.output
    assert _is_whole_report(lab / "out") and not _siblings(lab)


def test_the_parent_folder_deleted_mid_run_is_exit_2_and_nothing_is_left(lab, monkeypatch):
    _delete_during_vtu(monkeypatch, lambda tmp: lab / "reports")
    result = _run("--out", "reports/out")
    _clean_failure(result, "reports/out", "removed", "nothing was written")
    assert sorted(p.name for p in lab.iterdir()) == ["scene.toml"]
