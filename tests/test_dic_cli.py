"""`vlab dic`: the folder it writes, and bad inputs refused with exit 2 and nothing written."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.dic import speckle
from vlab.dic.images import read_grey, write_grey

SHAPE = (128, 144)
PATTERN = speckle.make_pattern(SHAPE, size=4.0, density=0.5, seed=5)


@pytest.fixture(scope="module")
def images(tmp_path_factory):
    folder = tmp_path_factory.mktemp("images")
    ref = speckle.render(PATTERN, SHAPE, supersample=2)
    write_grey(folder / "ref.tif", ref, 16)
    write_grey(folder / "a.tif", speckle.render(PATTERN, SHAPE, speckle.translation(0.4, 0.2), supersample=2), 16)
    write_grey(folder / "b.png", speckle.render(PATTERN, SHAPE, speckle.homogeneous(4e-3, 0.0, (70, 60)),
                                                supersample=2) / 257, 8)
    return folder


def _run(*args):
    return CliRunner().invoke(app, ["dic", *map(str, args)])


def test_images_round_trip_8_and_16_bit(tmp_path):
    levels = np.arange(200 * 3, dtype=float).reshape(20, 30) * 100
    for name, bits in (("x.png", 16), ("x.tif", 16), ("y.png", 8), ("y.tif", 8)):
        write_grey(tmp_path / name, levels, bits)
        assert np.array_equal(read_grey(tmp_path / name), np.clip(levels, 0, 2 ** bits - 1))


def test_pair_and_sequence_written(images, tmp_path):
    out = tmp_path / "dic"
    res = _run(images / "ref.tif", images / "a.tif", images / "b.png", "--out", out)
    assert res.exit_code == 0, res.output
    assert "b is 8-bit, the reference 16-bit" in res.output  # allowed (ZNSSD), and said
    assert sorted(p.name for p in (out / "fields").iterdir()) == ["a.csv", "b.csv"]
    with open(out / "fields" / "a.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0])[:7] == ["x_px", "y_px", "u_px", "v_px", "exx", "eyy", "exy"]
    u = np.array([float(r["u_px"]) for r in rows])
    v = np.array([float(r["v_px"]) for r in rows])
    assert np.allclose(u, 0.4, atol=0.01) and np.allclose(v, 0.2, atol=0.01)
    data = json.loads((out / "dic.json").read_text())
    assert data["bit_depth"] == {str(images / "ref.tif"): "16-bit", "a": "16-bit", "b": "8-bit"}
    assert data["settings"]["subset"] == 31 and data["images"]["a"]["converged_share"] == 1.0
    assert abs(data["images"]["b"]["mean_exx"] - 4e-3) < 2e-4  # 8-bit quantised
    assert (out / "index.html").exists() and (out / "maps" / "b.png").exists()


def test_subsets_without_texture_are_empty_cells_with_their_status(tmp_path):
    """A reference speckled on its left half only: the subsets on the uniform right half are
    'no texture' in the CSV (empty u, v, strains) and in the printed summary; the rest correlate."""
    ref = speckle.render(PATTERN, SHAPE, supersample=2)
    ref[:, 72:] = 30000.0
    shifted = speckle.render(PATTERN, SHAPE, speckle.translation(0.4, 0.2), supersample=2)
    shifted[:, 72:] = 30000.0
    write_grey(tmp_path / "half.tif", ref, 16)
    write_grey(tmp_path / "moved.tif", shifted, 16)
    out = tmp_path / "dic"
    res = _run(tmp_path / "half.tif", tmp_path / "moved.tif", "--out", out)
    assert res.exit_code == 0, res.output
    assert "no texture" in res.output
    with open(out / "fields" / "moved.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    flat = [r for r in rows if float(r["x_px"]) - 15 > 72]  # the subset lies wholly on the uniform half
    assert flat and all(r["status"] == "no texture" and r["u_px"] == "" and r["exx"] == "" for r in flat)
    textured = [r for r in rows if float(r["x_px"]) + 15 < 72]
    assert textured and all(r["status"] == "ok" and abs(float(r["u_px"]) - 0.4) < 0.01 for r in textured)


def test_bad_inputs_exit_2_and_write_nothing(images, tmp_path):
    text = tmp_path / "notes.png"
    text.write_text("not an image")
    small = tmp_path / "small.png"
    write_grey(small, np.zeros((64, 64)), 8)
    rgb = tmp_path / "rgb.png"
    from PIL import Image
    Image.fromarray(np.zeros((*SHAPE, 3), np.uint8)).save(rgb)
    flat = tmp_path / "flat.png"
    write_grey(flat, np.full(SHAPE, 100.0), 8)
    cases = [((images / "ref.tif", text), "not a readable image"),
             ((images / "ref.tif", small), "must have the reference's size"),
             ((images / "ref.tif", rgb), "grey image"),
             ((images / "ref.tif", tmp_path / "missing.tif"), "no such file"),
             ((tmp_path / "missing.tif", images / "a.tif"), "no such file"),
             ((flat, flat), "has texture"),
             ((images / "ref.tif", images / "a.tif", images / "a.tif"), "same stem"),
             ((images / "ref.tif", images / "a.tif", "--subset", "30"), "--subset"),
             ((images / "ref.tif", images / "a.tif", "--strain-window", "1"), "--strain-window"),
             ((images / "ref.tif", images / "a.tif", "--subset", "201"), "does not fit")]
    for args, message in cases:
        out = tmp_path / "out"
        res = _run(*args, "--out", out)
        assert res.exit_code == 2, (args, res.output)
        assert message in res.output, res.output
        assert not out.exists()


def test_out_folder_holding_someone_s_files_is_refused_before_any_work(images, tmp_path):
    """--out naming a folder vlab did not make: exit 2 naming it, before correlating, and the
    folder's files untouched; --out naming a file is refused as well."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("years of work")
    res = _run(images / "ref.tif", images / "a.tif", "--out", out)
    assert res.exit_code == 2 and "--out" in res.output and "thesis.tex" in res.output, res.output
    assert "subsets converged" not in res.output  # refused before the correlation
    assert sorted(p.name for p in out.iterdir()) == ["thesis.tex"]
    assert (out / "thesis.tex").read_text() == "years of work"
    a_file = tmp_path / "notes.txt"
    a_file.write_text("keep")
    res = _run(images / "ref.tif", images / "a.tif", "--out", a_file)
    assert res.exit_code == 2 and "--out" in res.output, res.output
    assert a_file.read_text() == "keep"
