"""What the report's pictures say: biaxial tests draw their own plots, a uniform field is one
colour with its value, a cyclic test is rendered at its peak and its end, titled so."""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from vlab.report.writer import ReportOptions, write_run
from vlab.run import run_scene
from vlab.scene import apply_overrides, parse_scene

SPECIMENS = Path(__file__).resolve().parents[1] / "specimens"


def _report(name: str, tmp_path, overrides: dict):
    path = SPECIMENS / f"{name}.toml"
    raw = apply_overrides(tomllib.loads(path.read_text(encoding="utf-8")), overrides)
    scene = parse_scene(raw, origin=path.name, base_dir=path.parent)
    folder = tmp_path / name
    data = write_run(run_scene(scene), folder, path.read_text(encoding="utf-8"), ReportOptions())
    return data, folder, json.loads((folder / "comparison.json").read_text())


@pytest.fixture(scope="module")
def sheet(tmp_path_factory):
    return _report("sheet-equibiaxial", tmp_path_factory.mktemp("sheet"), {"test.steps": 3})


@pytest.fixture(scope="module")
def cyclic(tmp_path_factory):
    return _report("block-mullins-cyclic", tmp_path_factory.mktemp("cyclic"), {"test.steps": 4})


def test_a_biaxial_report_draws_both_axes_and_the_thickness_not_the_uniaxial_plots(sheet):
    data, folder, _ = sheet
    assert (folder / "stress_strain.png").is_file() and (folder / "thickness_strain.png").is_file()
    assert not (folder / "lateral_strain.png").exists()
    page = (folder / "index.html").read_text(encoding="utf-8")
    assert "apparent Poisson" not in page and "along x (left) and y (right)" in page


def test_an_equibiaxial_sheet_renders_as_one_colour_with_its_value(sheet):
    data, folder, summary = sheet
    meta = summary["renders"]["side_by_side"]
    assert meta["uniform"] is not None and meta["uniform"] > 0
    x0, y0, x1, y1 = meta["panels"][0]
    panel = np.asarray(Image.open(folder / meta["file"]).convert("RGB"), dtype=int)[y0:y1, x0:x1]
    body = panel[(panel < 250).any(axis=-1) & (np.ptp(panel, axis=-1) > 40)]  # coloured (not edge/grey) pixels
    _, counts = np.unique(body // 8, axis=0, return_counts=True)
    # one colour (75 % of the pixels in one bin; the rest: edge blends); the round-off colour scale gave 12 %
    assert counts.max() > 0.5 * len(body), counts.max() / len(body)


def test_a_cyclic_test_is_rendered_at_its_peak_and_its_end_titled_so(cyclic):
    data, folder, summary = cyclic
    peak, end = summary["renders"]["side_by_side"], summary["renders"]["end"]
    assert peak["states"] == [f"peak stretch {max(data['curve']['stretch']):.4g}"]
    assert end["states"][0].startswith("end of test")
    assert not any("stopped" in s for s in peak["states"] + end["states"])
    assert peak["clim"][0] >= 0.0 and end["clim"][0] >= 0.0  # von Mises: never below 0
