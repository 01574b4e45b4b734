"""One copy of plotly.js per reports folder: every report's view3d.html points at
``<reports root>/_assets/plotly-<version>.min.js`` (relative, so it opens offline and moves with its
_assets folder) instead of shipping 4.8 MB each; the shared file is written only where none of its
name exists or used where its bytes are vlab's: a foreign file of that name is never replaced, and
sharing never fails a report (the report then carries its own copy, as before)."""

import html
import json
import re
import shutil
from pathlib import Path

import plotly
import pytest

from vlab.report.interactive import PLOTLY_JS, plotly_source
from vlab.report.shared import ASSETS
from vlab.report.writer import ReportOptions, shared_root, write_run

PACKAGE_JS = Path(plotly.__file__).parent / "package_data" / PLOTLY_JS
SHARED = f"plotly-{plotly.__version__}.min.js"
SMALL = {"mesh": {"size": 10.0}, "test": {"steps": 2}}


def plotly_src(page: Path) -> str:
    return html.unescape(re.search(r'<script src="([^"]+)"></script>', page.read_text(encoding="utf-8")).group(1))


@pytest.fixture(scope="module")
def tiny_run():
    from vlab.cli import default_scene_path
    from vlab.run import run_scene
    from vlab.scene import apply_overrides, parse_scene
    import tomllib

    path = default_scene_path()
    raw = apply_overrides(tomllib.loads(path.read_text(encoding="utf-8")), {"mesh.size": 10.0, "test.steps": 2})
    return run_scene(parse_scene(raw, origin=path.name, base_dir=path.parent))


def test_two_reports_share_one_plotly_beside_them(tiny_run, tmp_path):
    options = ReportOptions(render=True, vtu=False)
    for name in ("a", "b"):
        write_run(tiny_run, tmp_path / name, None, options)
    assert sorted(p.name for p in (tmp_path / ASSETS).iterdir()) == [SHARED]
    for name in ("a", "b"):
        folder = tmp_path / name
        src = plotly_src(folder / "view3d.html")
        assert src == f"../{ASSETS}/{SHARED}"
        assert (folder / src).resolve().read_bytes() == PACKAGE_JS.read_bytes()  # the page's script, offline
        assert not list(folder.rglob("*.js")), list(folder.rglob("*.js"))  # no 4.8 MB copy per report
        manifest = json.loads((folder / ".vlab-report.json").read_text())
        assert not any("plotly" in f for f in manifest["files"])  # the shared file is not the report's
        view = json.loads((folder / "comparison.json").read_text())["view3d"]
        assert view["plotly_shared"] == src and view["files"] == ["view3d.html"]
    moved = tmp_path / "elsewhere" / "a"  # moved with its _assets folder: the page still finds plotly.js
    moved.parent.mkdir()
    shutil.move(tmp_path / "a", moved)
    shutil.copytree(tmp_path / ASSETS, moved.parent / ASSETS)
    assert (moved / plotly_src(moved / "view3d.html")).is_file()


def test_a_foreign_file_of_that_name_is_never_replaced(tmp_path):
    (tmp_path / ASSETS).mkdir()
    (tmp_path / ASSETS / SHARED).write_text("the user's own file")
    report = tmp_path / "r"
    report.mkdir()
    script, own, shared = plotly_source(report, tmp_path, inline=False)
    assert (tmp_path / ASSETS / SHARED).read_text() == "the user's own file"
    assert shared is None and own == [PLOTLY_JS] and script == f'<script src="{PLOTLY_JS}"></script>'
    assert (report / PLOTLY_JS).read_bytes() == PACKAGE_JS.read_bytes()  # the report carries its own copy


def test_an_identical_file_is_used_and_nothing_else_is_written(tmp_path):
    (tmp_path / ASSETS).mkdir()
    shutil.copyfile(PACKAGE_JS, tmp_path / ASSETS / SHARED)
    (tmp_path / "r").mkdir()
    _, own, shared = plotly_source(tmp_path / "r", tmp_path, inline=False)
    assert shared == f"../{ASSETS}/{SHARED}" and own == [] and not list((tmp_path / "r").iterdir())
    assert sorted(p.name for p in (tmp_path / ASSETS).iterdir()) == [SHARED]  # no temporary file left


def test_a_file_named_assets_or_a_read_only_root_does_not_fail_the_report(tmp_path):
    (tmp_path / ASSETS).write_text("not a folder")
    (tmp_path / "r").mkdir()
    _, own, shared = plotly_source(tmp_path / "r", tmp_path, inline=False)
    assert shared is None and own == [PLOTLY_JS] and (tmp_path / ASSETS).read_text() == "not a folder"
    locked = tmp_path / "locked"
    (locked / "r").mkdir(parents=True)
    locked.chmod(0o555)  # (root writes anyway: then the copy is shared)
    try:
        if not (locked / ASSETS).exists():
            _, own, shared = plotly_source(locked / "r", locked, inline=False)
            assert (shared is None and own == [PLOTLY_JS]) or (own == [] and (locked / ASSETS / SHARED).is_file())
    finally:
        locked.chmod(0o755)


def test_a_report_named_assets_keeps_its_own_copy(tmp_path):
    assert shared_root(tmp_path / ASSETS) is None and shared_root(tmp_path / "x") == tmp_path.resolve()


def test_single_file_reports_still_inline_plotly(tmp_path):
    script, own, shared = plotly_source(tmp_path, tmp_path.parent, inline=True)
    assert own == [] and shared is None and len(script) > 4_000_000 and not (tmp_path.parent / ASSETS).exists()


def test_a_file_put_there_meanwhile_is_kept(tmp_path, monkeypatch):
    import vlab.report.shared as shared_mod

    def someone_was_first(src, dest):
        Path(dest).write_text("made by someone else between vlab's check and its link")
        raise FileExistsError(dest)

    monkeypatch.setattr(shared_mod.os, "link", someone_was_first)
    (tmp_path / "r").mkdir()
    _, own, shared = plotly_source(tmp_path / "r", tmp_path, inline=False)
    assert shared is None and own == [PLOTLY_JS]
    assert (tmp_path / ASSETS / SHARED).read_text().startswith("made by someone else")
    assert sorted(p.name for p in (tmp_path / ASSETS).iterdir()) == [SHARED]


def test_without_hard_links_the_copy_is_made_exclusively(tmp_path, monkeypatch):
    import vlab.report.shared as shared_mod

    def no_links(src, dest):
        raise PermissionError(1, "Operation not permitted")

    monkeypatch.setattr(shared_mod.os, "link", no_links)
    (tmp_path / "r").mkdir()
    _, own, shared = plotly_source(tmp_path / "r", tmp_path, inline=False)
    assert shared == f"../{ASSETS}/{SHARED}" and own == []
    assert (tmp_path / ASSETS / SHARED).read_bytes() == PACKAGE_JS.read_bytes()
    assert sorted(p.name for p in (tmp_path / ASSETS).iterdir()) == [SHARED]


def test_a_failed_report_leaves_no_shared_folder_in_the_parents_it_made(tmp_path):
    from vlab.report.folder import report_folder

    target = tmp_path / "new" / "deeper" / "r"
    with pytest.raises(RuntimeError):
        with report_folder(target) as tmp:
            _, own, shared = plotly_source(tmp, target.parent, inline=False)
            assert shared and (target.parent / ASSETS / SHARED).is_file()
            raise RuntimeError("a figure failed")
    assert list(tmp_path.iterdir()) == []  # nothing half-written: not even the shared copy


def test_a_failed_report_keeps_the_shared_folder_of_an_existing_reports_folder(tmp_path):
    from vlab.report.folder import report_folder

    with pytest.raises(RuntimeError):
        with report_folder(tmp_path / "r") as tmp:
            plotly_source(tmp, tmp_path, inline=False)
            raise RuntimeError("a figure failed")
    assert sorted(p.name for p in tmp_path.iterdir()) == [ASSETS]  # other reports may use it already
