"""Report folders (#16 item 1): vlab replaces only a folder it made (manifest), refuses a user's
non-empty folder with exit 2 naming it, --force never takes the scene file, the cache, the
current or the home folder; every folder-writing command goes through the one writer; report
folders get umask permissions; orphans of a killed run are cleaned, nothing else."""

from __future__ import annotations

import json
import os
import stat

import pytest
from typer.testing import CliRunner

from vlab.cli import app
from helpers_scenes import block_toml

runner = CliRunner()

SCENE = block_toml("folder-block")
FAST = ["--no-render", "--no-estimate", "-q"]


@pytest.fixture
def lab(tmp_path, monkeypatch):
    """A user's folder: the scene, a documents folder with a file; cwd is the folder."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.toml").write_text(SCENE)
    (tmp_path / "mydocs").mkdir()
    (tmp_path / "mydocs" / "thesis.txt").write_text("years of work")
    return tmp_path


def _run(*args):
    return runner.invoke(app, ["run", "scene.toml", *args, *FAST])


def test_a_user_folder_with_files_is_refused_with_exit_2_naming_it_and_left_intact(lab):
    result = _run("--out", "mydocs")
    assert result.exit_code == 2, result.output
    assert "mydocs" in result.output and "thesis.txt" in result.output and "--force" in result.output
    assert (lab / "mydocs" / "thesis.txt").read_text() == "years of work"
    assert sorted(p.name for p in (lab / "mydocs").iterdir()) == ["thesis.txt"]


def test_out_dot_is_refused_and_the_scene_survives_even_with_force(lab):
    for extra in ([], ["--force"]):
        result = _run("--out", ".", *extra)
        assert result.exit_code == 2, result.output
        assert "current folder" in result.output or "scene file" in result.output, result.output
        assert (lab / "scene.toml").read_text() == SCENE


def test_force_replaces_a_user_folder_but_never_one_holding_the_scene_or_the_cache(lab):
    result = _run("--out", "mydocs", "--force")
    assert result.exit_code == 0, result.output
    assert (lab / "mydocs" / "results.json").is_file() and not (lab / "mydocs" / "thesis.txt").exists()
    (lab / "box").mkdir()
    (lab / "box" / "scene.toml").write_text(SCENE)
    result = runner.invoke(app, ["run", "box/scene.toml", "--out", "box", "--force", *FAST])
    assert result.exit_code == 2 and "scene file" in result.output, result.output
    assert (lab / "box" / "scene.toml").read_text() == SCENE
    (lab / "reports" / ".cache" / "ab").mkdir(parents=True)
    (lab / "reports" / ".cache" / "ab" / "entry.json").write_text("{}")
    result = _run("--out", "reports", "--force")
    assert result.exit_code == 2 and "cache" in result.output, result.output
    assert (lab / "reports" / ".cache" / "ab" / "entry.json").is_file()


def test_vlab_replaces_its_own_report_folder_whose_manifest_lists_every_file(lab):
    from vlab.report.folder import MANIFEST

    assert _run("--out", "out").exit_code == 0
    manifest = json.loads((lab / "out" / MANIFEST).read_text())
    files = {str(p.relative_to(lab / "out")) for p in (lab / "out").rglob("*") if p.is_file()}
    assert set(manifest["files"]) == files - {MANIFEST} and "results.json" in manifest["files"]
    assert manifest["kind"] == "run"
    assert _run("--out", "out").exit_code == 0  # its own folder: replaced without --force
    (lab / "out" / "notes.txt").write_text("mine")  # a file vlab did not write makes it the user's
    result = _run("--out", "out")
    assert result.exit_code == 2 and "notes.txt" in result.output, result.output
    assert (lab / "out" / "notes.txt").read_text() == "mine"
    assert not [p for p in lab.iterdir() if ".vlab-" in p.name]  # no temporary sibling left


def test_report_folders_and_files_get_umask_permissions_not_0700(lab):
    old = os.umask(0o022)
    try:
        assert _run("--out", "perm").exit_code == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE((lab / "perm").stat().st_mode) == 0o755
    assert stat.S_IMODE((lab / "perm" / "results.json").stat().st_mode) == 0o644


@pytest.mark.parametrize("command", [
    ["compare", "scene.toml", "--models", "linear"],
    ["sweep", "scene.toml", "--set", "material.nu=0.3"],
    ["cost", "scene.toml", "--levels", "3"],
    ["stability", "--fast"],
])
def test_every_folder_writing_command_refuses_a_user_folder_before_any_work(lab, command):
    result = runner.invoke(app, [*command, "--out", "mydocs", "-q"])
    assert result.exit_code == 2, result.output
    assert "mydocs" in result.output and "not made by vlab" in result.output
    assert sorted(p.name for p in (lab / "mydocs").iterdir()) == ["thesis.txt"]


def _orphan(parent, name, pid, marker=True):
    from vlab.report.folder import _HOST, MARKER

    folder = parent / f".{name}.vlab-tmp-{_HOST}-{pid}-0123abcd"
    folder.mkdir()
    (folder / "results.json").write_text("{}")
    if marker:
        (folder / MARKER).write_text("{}")
    return folder


def test_orphans_of_a_killed_run_are_removed_on_the_next_run_and_nothing_else(lab):
    from vlab.report.folder import clean_orphans

    dead = 2**22 + 12345  # above the default pid_max of 4,194,304: no such process
    orphan = _orphan(lab, "out", dead)
    unmarked = _orphan(lab, "look-alike", dead, marker=False)  # same name pattern, not vlab's marker
    alive = _orphan(lab, "busy", os.getppid())  # a running process's folder (e.g. a concurrent writer)
    assert _run("--out", "out").exit_code == 0
    assert not orphan.exists()
    assert unmarked.exists() and alive.exists()
    assert clean_orphans(lab) == []


def test_force_never_replaces_the_home_folder_or_one_that_contains_it(lab, monkeypatch):
    home = lab / "home" / "me"
    home.mkdir(parents=True)
    (home / "notes.txt").write_text("mine")
    monkeypatch.setenv("HOME", str(home))
    for target in (str(home), str(lab / "home")):
        result = _run("--out", target, "--force")
        assert result.exit_code == 2 and "home folder" in result.output, result.output
    assert (home / "notes.txt").read_text() == "mine"
