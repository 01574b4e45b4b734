"""Bad input under attack (#16 items 7 and 8): every message printed verbatim (no rich markup), and
each of these is exit 2 naming the field or file with nothing left behind: --out that is a file,
read-only, on a full disk, a 300-character name; an imported mesh with a NaN coordinate,
overlapping grips, a corrupt .vtu, a .msh that is not a mesh; /dev/zero as the scene; a bogus or
unreachable --scheduler. A dogbone 0.01 mm wide is refused by its mesh quality (exit 2 naming
mesh.min_quality) or, with that check lowered, measured (its gauge marks on the faces are found)."""

from __future__ import annotations

import errno
import os
import shutil
import socket
import subprocess
import threading
import time
from pathlib import Path

import meshio
import numpy as np
import pytest
from typer.testing import CliRunner

from vlab.cli import app
from helpers_scenes import block_toml

runner = CliRunner()
SPECIMENS = Path(__file__).parent.parent / "specimens"
FAST = ["--no-render", "--no-estimate", "-q"]
SCENE = block_toml("contract-block")


@pytest.fixture
def lab(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.toml").write_text(SCENE)
    return tmp_path


def _tree(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


# --- item 7: verbatim text -------------------------------------------------------------------

def test_a_missing_section_is_named_with_its_brackets(lab):
    (lab / "scene.toml").write_text(SCENE.replace("[material]", "[materials]"))
    result = runner.invoke(app, ["run", "scene.toml", *FAST])
    assert result.exit_code == 2
    assert "section [materials]" in result.output, result.output


def test_a_value_with_closing_markup_is_shown_verbatim_not_a_crash(lab):
    (lab / "scene.toml").write_text(SCENE.replace('model = "linear"', 'model = "[/x][bold]neo"'))
    result = runner.invoke(app, ["run", "scene.toml", *FAST])
    assert result.exit_code == 2, result.output
    assert "[/x][bold]neo" in result.output


def test_a_completed_run_whose_out_holds_markup_exits_0_and_prints_the_path(lab):
    result = runner.invoke(app, ["run", "scene.toml", "--out", "r[/x]", *FAST])
    assert result.exit_code == 0, result.output
    assert "r[/x]/index.html" in result.output
    assert (lab / "r[" / "x]" / "results.json").is_file()


# --- item 8: output folders --------------------------------------------------------------------

def test_out_that_is_a_file_is_exit_2_and_leaves_no_hidden_folder(lab):
    (lab / "taken").write_text("a file")
    before = _tree(lab)
    result = runner.invoke(app, ["run", "scene.toml", "--out", "taken", *FAST])
    assert result.exit_code == 2 and "'taken' is a file" in result.output, result.output
    assert _tree(lab) == before


def test_a_300_character_name_is_exit_2_and_leaves_no_reports_folder(lab):
    name = "n" * 300
    result = runner.invoke(app, ["run", "scene.toml", "--out", f"reports/{name}", *FAST])
    assert result.exit_code == 2 and "300 characters" in result.output, result.output
    assert _tree(lab) == ["scene.toml"]


def test_a_full_disk_while_writing_is_exit_2_naming_the_folder_and_nothing_is_left(lab, monkeypatch):
    import vlab.report.writer as writer

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(writer, "write_columns_csv", full)
    result = runner.invoke(app, ["run", "scene.toml", "--out", "reports/full", *FAST])
    assert result.exit_code == 2, result.output
    assert "reports/full" in result.output and "No space left on device" in result.output
    assert _tree(lab) == ["scene.toml"]


@pytest.fixture
def tiny_mount(tmp_path):
    """A mount point of a 64 KiB tmpfs (needs root; skipped elsewhere); ``remount(ro)``."""
    point = tmp_path / "disk"
    point.mkdir()
    if os.geteuid() != 0 or not shutil.which("mount") or subprocess.run(
            ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(point)], capture_output=True).returncode:
        pytest.skip("mounting a tmpfs needs root")
    try:
        yield point
    finally:
        subprocess.run(["umount", "-l", str(point)], capture_output=True)


def test_a_really_full_disk_is_exit_2_and_the_disk_is_left_as_it_was(lab, tiny_mount):
    (tiny_mount / "keep.txt").write_text("user data")
    result = runner.invoke(app, ["run", "scene.toml", "--out", str(tiny_mount / "report"), *FAST])
    assert result.exit_code == 2, result.output
    assert "No space left on device" in result.output, result.output
    assert _tree(tiny_mount) == ["keep.txt"]


def test_a_read_only_place_is_exit_2_naming_it(lab, tiny_mount):
    subprocess.run(["mount", "-o", "remount,ro", str(tiny_mount)], check=True)
    result = runner.invoke(app, ["run", "scene.toml", "--out", str(tiny_mount / "report"), *FAST])
    assert result.exit_code == 2, result.output
    assert "read-only" in result.output and str(tiny_mount) in result.output


# --- item 8: imported meshes ------------------------------------------------------------------

@pytest.fixture
def bar(lab):
    shutil.copytree(SPECIMENS / "meshes", lab / "meshes")
    text = (SPECIMENS / "mesh-import-bar.toml").read_text()
    return lambda **kw: _scene_with(lab, text, **kw)


def _scene_with(lab, text, file=None, replace=()):
    if file:
        text = text.replace("meshes/bar.msh", file)
    for old, new in replace:
        text = text.replace(old, new)
    (lab / "bar.toml").write_text(text)
    return runner.invoke(app, ["run", "bar.toml", *FAST])


def test_an_imported_mesh_with_a_nan_coordinate_is_exit_2_naming_the_file(bar, lab):
    m = meshio.read(lab / "meshes" / "bar.msh")
    m.points[5, 0] = np.nan
    meshio.write(lab / "meshes" / "nan.msh", m, file_format="gmsh22", binary=False)
    result = bar(file="meshes/nan.msh")
    assert result.exit_code == 2 and "specimen.file" in result.output and "non-finite" in result.output, \
        result.output


@pytest.mark.parametrize("name, content", [("corrupt.vtu", "<VTKFile type='UnstructuredGrid'><garb"),
                                           ("notmesh.msh", "hello\nthis is not a mesh\n")])
def test_a_file_meshio_cannot_read_is_exit_2_naming_it_not_meshios_exit(bar, lab, name, content):
    (lab / "meshes" / name).write_text(content)
    result = bar(file=f"meshes/{name}")
    assert result.exit_code == 2, result.output
    assert "specimen.file" in result.output and name in result.output


def test_overlapping_grips_are_exit_2_naming_the_grips(bar):
    result = bar(replace=[('right = "tab_right"', 'right = "tab_left"')])
    assert result.exit_code == 2 and "specimen.grips" in result.output, result.output


def test_a_dogbone_0_01_mm_wide_is_refused_by_quality_or_measured_with_its_marks_found():
    from vlab.run import run_scene
    from vlab.scene import SceneError, parse_scene

    raw = {"name": "thin", "specimen": {"shape": "dogbone", "standard": "ISO 527-2 1A", "width": 0.01},
           "mesh": {"size": 2.5, "cell": "tet"}, "material": {"model": "linear", "E": 10.0, "nu": 0.3},
           "test": {"kind": "uniaxial", "stretch": 1.01, "steps": 1}}
    with pytest.raises(SceneError, match="mesh.min_quality"):
        run_scene(parse_scene(raw))
    raw["mesh"]["min_quality"] = 0.001  # the transverse marks sit on faces 0.01 mm apart
    result = run_scene(parse_scene(raw))
    assert result.converged and abs(result.constants.E - 10.0) < 0.1


# --- item 8: the scene file and the scheduler -------------------------------------------------

def test_dev_zero_as_the_scene_is_exit_2_at_once(lab):
    start = time.perf_counter()
    result = runner.invoke(app, ["run", "/dev/zero", *FAST])
    assert result.exit_code == 2 and "/dev/zero" in result.output and "regular file" in result.output
    assert time.perf_counter() - start < 5.0


def test_a_huge_scene_file_is_refused_by_size(lab):
    (lab / "big.toml").write_text("# " + "x" * (2 << 20))
    result = runner.invoke(app, ["run", "big.toml", *FAST])
    assert result.exit_code == 2 and "larger than" in result.output, result.output


class _Garbage:
    """A TCP server that answers every connection with 64 bytes of 0xff (a length of 2^64 − 1)."""

    def __enter__(self):
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen()
        threading.Thread(target=self._serve, daemon=True).start()
        return f"tcp://127.0.0.1:{self.sock.getsockname()[1]}"

    def _serve(self):
        while True:
            try:
                conn, _ = self.sock.accept()
                conn.sendall(b"\xff" * 64)
            except OSError:
                return

    def __exit__(self, *exc):
        self.sock.close()


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("address", ["garbage", "tcp://:80", "tcp://host:99999", "http://[/x]:1", "GARBAGE",
                                     "unreachable", "refused"])
def test_a_bogus_or_unreachable_scheduler_is_exit_2_naming_the_option(lab, address):
    if address == "GARBAGE":
        with _Garbage() as address:
            result = runner.invoke(app, ["sweep", "scene.toml", "--set", "material.nu=0.31", "--scheduler",
                                         address, "--cache", "c", "-q"])
    else:
        address = {"refused": f"tcp://127.0.0.1:{_free_port()}",
                   "unreachable": "tcp://192.0.2.1:8786"}.get(address, address)  # TEST-NET-1: no route
        result = runner.invoke(app, ["sweep", "scene.toml", "--set", "material.nu=0.31", "--scheduler", address,
                                     "--cache", "c", "-q"])
    assert result.exit_code == 2, (result.output, result.exception)
    assert "--scheduler" in result.output and address in result.output
    assert not (lab / "reports").exists()
