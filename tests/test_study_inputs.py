"""Studies under attack (#16 items 2 and 3): the cache key covers the bytes of referenced files,
entries are validated on read (edited, NaN, [], {}, a folder: recomputed, never served),
--cache FILE is an error; scene paths resolve against the scene's folder in sweep, cost and the
accuracy estimate from any folder (also in Dask workers); a study whose every point is invalid
exits non-zero."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import meshio
import pytest
from typer.testing import CliRunner

from vlab.cli import app

runner = CliRunner()
SPECIMENS = Path(__file__).parent.parent / "specimens"


@pytest.fixture(scope="module")
def scheduler():
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0",
                      scheduler_port=0) as local:
        yield local.scheduler_address


@pytest.fixture
def project(tmp_path, monkeypatch):
    """specimens/mesh-import-bar.toml and its mesh in ``project/``; cwd is another folder."""
    root = tmp_path / "project"
    shutil.copytree(SPECIMENS / "meshes", root / "meshes")
    text = (SPECIMENS / "mesh-import-bar.toml").read_text().replace("steps = 4", "steps = 1")
    (root / "bar.toml").write_text(text.replace("stretch = 1.1", "stretch = 1.01"))
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "elsewhere")
    return root


def _sweep(project, scheduler, out="sweep", *extra):
    result = runner.invoke(app, ["sweep", str(project / "bar.toml"), "--set", "material.nu=0.3", "--scheduler",
                                 scheduler, "--cache", "cache", "--out", out, "-q", *extra])
    data = json.loads((Path(out) / "sweep.json").read_text()) if (Path(out) / "sweep.json").exists() else None
    return result, data


def test_a_sweep_started_elsewhere_finds_the_scenes_mesh_and_a_changed_mesh_is_recomputed(project, scheduler):
    result, data = _sweep(project, scheduler)
    assert result.exit_code == 0, result.output
    run = data["runs"][0]
    assert run["status"] == "ok" and abs(run["measured"]["E"] - 10.0) < 0.3
    m = meshio.read(project / "meshes" / "bar.msh")
    m.points[:, 1] *= 2.0  # twice as wide, same area in the scene: the measured E doubles
    meshio.write(project / "meshes" / "bar.msh", m, file_format="gmsh22", binary=False)
    result, data = _sweep(project, scheduler)
    assert result.exit_code == 0, result.output
    run = data["runs"][0]
    assert not run["cache_hit"] and data["meta"]["computed"] == 1
    assert abs(run["measured"]["E"] - 20.0) < 0.8, run["measured"]


def _entry(cache: Path) -> Path:
    (entry,) = cache.glob("*/*.json")
    return entry


@pytest.fixture(scope="module")
def first_sweep(tmp_path_factory, scheduler):
    """The project's one-point sweep computed once: (project, cache folder, its measured values)."""
    top = tmp_path_factory.mktemp("first")
    root = top / "project"
    shutil.copytree(SPECIMENS / "meshes", root / "meshes")
    text = (SPECIMENS / "mesh-import-bar.toml").read_text().replace("steps = 4", "steps = 1")
    (root / "bar.toml").write_text(text.replace("stretch = 1.1", "stretch = 1.01"))
    result = runner.invoke(app, ["sweep", str(root / "bar.toml"), "--set", "material.nu=0.3", "--scheduler",
                                 scheduler, "--cache", str(top / "cache"), "--out", str(top / "sweep"), "-q"])
    assert result.exit_code == 0, result.output
    return root, top / "cache", json.loads((top / "sweep" / "sweep.json").read_text())["runs"][0]["measured"]


@pytest.mark.parametrize("corrupt", ["E=12345", "NaN", "[]", "{}", "folder", "truncated"])
def test_a_corrupted_cache_entry_is_recomputed_never_served(first_sweep, tmp_path, monkeypatch, scheduler, corrupt):
    root, clean, measured = first_sweep
    monkeypatch.chdir(tmp_path)
    shutil.copytree(clean, "cache")
    entry = _entry(Path("cache"))
    data = json.loads(entry.read_text())
    if corrupt == "E=12345":
        data["measured"]["E"] = 12345.0
        entry.write_text(json.dumps(data))
    elif corrupt == "NaN":
        entry.write_text(json.dumps(data).replace(str(data["measured"]["nu"]), "NaN"))
    elif corrupt == "folder":
        entry.unlink()
        entry.mkdir()
    elif corrupt == "truncated":
        entry.write_text(entry.read_text()[:100])
    else:
        entry.write_text(corrupt)
    result, again = _sweep(root, scheduler, "sweep2")
    assert result.exit_code == 0, (result.output, result.exception)
    run = again["runs"][0]
    assert not run["cache_hit"] and run["measured"] == measured


def test_cache_that_is_a_file_is_exit_2(project, scheduler):
    Path("cache").write_text("not a folder")
    result, _ = _sweep(project, scheduler)
    assert result.exit_code == 2 and "--cache 'cache' is a file" in result.output, result.output
    assert Path("cache").read_text() == "not a folder"


def test_cost_from_elsewhere_reads_the_mesh_and_an_imported_mesh_is_not_coarsened(project, scheduler):
    result = runner.invoke(app, ["cost", str(project / "bar.toml"), "--levels", "3", "--orders", "1", "--cells",
                                 "tet", "--scheduler", scheduler, "--cache", "cache", "--out", "cost", "-q"])
    data = json.loads(Path("cost/cost.json").read_text())
    statuses = [r["status"] for r in data["runs"]]
    assert "does not exist" not in json.dumps(data["runs"])
    # no mesh-size family (each of its points was refused: mesh.size does not apply to a file's mesh):
    # steps, rtol and models, all run, with errors against the tightest-rtol run, and the reason said
    assert not any(r["label"]["knob"].startswith("mesh size") for r in data["runs"])
    assert len(statuses) >= 8 and set(statuses) == {"ok"}, [r.get("diagnosis") for r in data["runs"]]
    assert sum(e is not None and e["max"] is not None for e in data["errors"]) == len(statuses) - 1  # not the reference
    assert data["recommended"] is not None and "No run completed" not in data["recommendation"]
    assert "vlab does not refine a file's mesh" in data["meta"]["fixed_mesh"]
    assert result.exit_code == 0, result.output


def test_the_accuracy_estimate_from_elsewhere_says_an_imported_mesh_is_not_coarsened(project):
    from vlab.run import run_scene
    from vlab.scene import load_scene
    from vlab.study.estimate import accuracy_estimate

    scene = load_scene(Path("..") / "project" / "bar.toml")
    est = accuracy_estimate(run_scene(scene))
    assert not est["available"] and "does not exist" not in est["reason"]
    assert "imported" in est["reason"], est["reason"]


def test_a_cost_study_whose_every_point_is_invalid_exits_2(tmp_path, monkeypatch, scheduler):
    monkeypatch.chdir(tmp_path)
    scene = (SPECIMENS / "block-neo-hookean.toml").read_text().replace("[mesh]", "[mesh]\nmax_dofs = 3")
    (tmp_path / "s.toml").write_text(scene)
    result = runner.invoke(app, ["cost", "s.toml", "--levels", "3", "--orders", "1", "--cells", "hex",
                                 "--scheduler", scheduler, "--cache", "cache", "-q"])
    assert result.exit_code == 2, result.output
    assert "every run is invalid" in result.output and "mesh.max_dofs" in result.output
