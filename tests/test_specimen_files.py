"""Every scene in specimens/ runs as a test, on a coarser mesh and fewer steps than its own."""

import tomllib
from pathlib import Path

import pytest

from vlab.report.explain import viscoelastic_apparent
from vlab.report.writer import write_run
from vlab.run import run_scene
from vlab.scene import apply_overrides, parse_scene

FILES = sorted((Path(__file__).resolve().parents[1] / "specimens").glob("*.toml"))


def coarse(raw: dict) -> dict:
    """Up to twice the element size (keeping two elements across the narrowest width), at most
    four regular steps."""
    spec = parse_scene(raw, base_dir=FILES[0].parent).specimen
    overrides = {"test.steps": min(raw["test"].get("steps", 10), 4)}
    if spec.shape == "mesh":  # meshed already
        return apply_overrides(raw, overrides)
    narrow = {"dogbone": lambda: spec.dimensions.width, "block": lambda: min(spec.size[1:]),
              "sheet": lambda: spec.size[1],
              "cruciform": lambda: spec.dimensions.gauge_region / 2}[spec.shape]()
    size = raw["mesh"]["size"]
    if "gauge_size" not in raw["mesh"]:
        overrides["mesh.size"] = max(size, min(2 * size, narrow / 2))
    return apply_overrides(raw, overrides)


def test_the_folder_holds_scenes():
    assert len(FILES) >= 8


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_specimen_file_runs_on_a_coarse_mesh(path, tmp_path):
    raw = tomllib.loads(path.read_text(encoding="utf-8"))
    scene = parse_scene(coarse(raw), origin=path.name, base_dir=path.parent)
    result = run_scene(scene)
    assert result.converged, result.history.failure
    data = write_run(result, tmp_path / scene.name, path.read_text(encoding="utf-8"))
    E_in, nu_in = scene.material.moduli.E, scene.material.moduli.nu
    apparent = viscoelastic_apparent(data)
    if apparent is not None:  # a ramp measures the rate-dependent moduli, which the report states
        E_in, nu_in = apparent["E"], apparent["nu"]
    assert data["measured"]["E"] == pytest.approx(E_in, rel=0.03)
    assert data["measured"]["nu"] == pytest.approx(nu_in, rel=0.03)
    assert data["mesh"]["quality"]["min_quality"] >= scene.mesh.min_quality
