"""The guides beside every render (vlab.render.guides): the axis triad points where the scene's axes
point on screen, the scale bar is as long as its label says (checked against the rendered width of
a specimen of known size, not against the renderer's own arithmetic), neither overlaps a panel, and
the shear specimens are seen face-on: the camera looks along the normal of the shear plane."""

import numpy as np
import pytest
from PIL import Image

from vlab.post.snapshot import take_snapshot
from vlab.render.guides import AXIS_COLOURS, round_length
from vlab.render.specimens import RenderOptions, render_animation, render_side_by_side
from vlab.run import run_scene
from vlab.scene import parse_scene

SHEAR = {"shear": {"shape": "shear", "length": 20.0, "gap": 4.0, "depth": 10.0},
         "double-lap": {"shape": "double-lap", "length": 20.0, "gap": 4.0, "depth": 10.0, "plate_thickness": 2.0}}


def snapshot_of(specimen: dict, test: dict, size: float):
    scene = parse_scene({"name": "guides", "specimen": specimen, "mesh": {"size": size, "cell": "hex"},
                         "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.3}, "test": test,
                         "measure": {"modulus_points": 0}})
    return take_snapshot(run_scene(scene))


@pytest.fixture(scope="module")
def shear_snapshots():
    test = {"kind": "simple-shear", "grips": "plates", "shear": 0.5, "steps": 2}
    return {name: snapshot_of(spec, test, 2.0) for name, spec in SHEAR.items()}


@pytest.fixture(scope="module")
def block_snapshot():
    return snapshot_of({"shape": "block", "size": [20.0, 10.0, 5.0]},
                       {"kind": "uniaxial", "grips": "roller", "stretch": 1.2, "steps": 1}, 5.0)


def pixels(path) -> np.ndarray:
    return np.asarray(Image.open(path).convert("RGB"), dtype=float)


def dark_run(image: np.ndarray, row: float, x0: float, x1: float) -> int:
    """Length in pixels of the dark (black) run along ``row`` between columns x0 and x1."""
    line = image[int(round(row)), int(x0) - 5:int(x1) + 6].mean(axis=-1)
    dark = np.flatnonzero(line < 128)
    return int(dark[-1] - dark[0] + 1)


@pytest.mark.parametrize("extent, length", [(22.0, 2.0), (25.0, 5.0), (100.0, 20.0), (0.3, 0.05), (49.9, 5.0)])
def test_the_scale_bar_is_the_largest_1_2_5_length_within_a_fifth_of_the_extent(extent, length):
    assert round_length(extent) == pytest.approx(length)


@pytest.mark.parametrize("name", SHEAR)
def test_a_shear_specimen_is_seen_face_on_with_its_plates(shear_snapshots, name, tmp_path):
    snap = shear_snapshots[name]
    meta = render_side_by_side([snap], tmp_path / "face.png", RenderOptions())
    camera = meta["camera"]
    d = np.subtract(camera["position"], camera["focal_point"])
    normal = np.cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])  # shear direction x, gradient (gap) y
    assert np.allclose(d / np.linalg.norm(d), normal, atol=1e-12)
    triad = meta["guides"]["triad"]
    assert triad["x"]["screen"] == pytest.approx([1.0, 0.0]) and triad["y"]["screen"] == pytest.approx([0.0, 1.0])
    assert triad["z"]["end_on"] and triad["z"]["towards_viewer"]
    assert len(snap.plates) == {"shear": 2, "double-lap": 3}[name]
    moved = [p for p in snap.plates if abs(p[2][-1, 0]) > 0]  # the plate the machine pulls: γ × gap along x
    assert len(moved) == 1 and moved[0][2][-1] == pytest.approx([0.5 * 4.0, 0.0, 0.0], abs=1e-9)


def test_the_scale_bar_is_as_long_as_its_label_says(shear_snapshots, tmp_path):
    """Unloaded (frame 0) the shear specimen with its plates spans 1.5 L = 30 mm along x, the screen's
    right: its width in pixels gives the picture's pixels per mm independently of the renderer's
    camera arithmetic, and the bar's dark run must be its label's length at that scale."""
    meta = render_side_by_side([shear_snapshots["shear"]], tmp_path / "rest.png", RenderOptions(frame=0))
    image = pixels(tmp_path / "rest.png")
    x0, y0, x1, y1 = meta["panels"][0]
    columns = (image[y0:y1, x0:x1] < 245).any(axis=-1).any(axis=0)
    spanned = np.flatnonzero(columns)
    per_mm = (spanned[-1] - spanned[0] + 1) / 30.0
    bar = meta["guides"]["scale_bar"]
    assert bar["label"] == f"{bar['mm']:g} mm" and bar["mm"] == 5.0  # 30 mm / 5 = 6 -> 5 mm
    bx0, by0, bx1, by1 = bar["box"]
    drawn = dark_run(image, (by0 + by1) / 2, bx0, bx1)
    assert drawn == pytest.approx(bar["mm"] * per_mm, rel=0.02)
    assert drawn == pytest.approx(bar["pixels"], abs=2)


def test_the_triad_points_along_the_axes_as_the_camera_sees_them(block_snapshot, tmp_path):
    meta = render_side_by_side([block_snapshot], tmp_path / "block.png", RenderOptions())
    image = pixels(tmp_path / "block.png")
    triad = meta["guides"]["triad"]
    bx0, by0, bx1, by1 = (int(round(v)) for v in triad["box"])
    cx, cy = triad["centre"]
    rows, cols = np.mgrid[by0:by1, bx0:bx1]
    for name, colour in AXIS_COLOURS.items():
        rgb = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)], dtype=float)
        mine = np.linalg.norm(image[by0:by1, bx0:bx1] - rgb, axis=-1) < 60
        assert mine.sum() > 20, f"axis {name} is not drawn"
        arrow = np.array([cols[mine].mean() - cx, cy - rows[mine].mean()])  # screen right, up
        assert not triad[name]["end_on"]
        assert arrow @ np.array(triad[name]["screen"]) / np.linalg.norm(arrow) / np.linalg.norm(triad[name]["screen"]) > 0.95


def test_the_guides_leave_every_panel_free(block_snapshot, shear_snapshots, tmp_path):
    for i, snaps in enumerate([[block_snapshot, block_snapshot], [shear_snapshots["double-lap"]]]):
        meta = render_side_by_side(snaps, tmp_path / f"free{i}.png", RenderOptions())
        guides = meta["guides"]
        for box in (guides["triad"]["box"], guides["scale_bar"]["box"], guides["scale_bar"]["label_box"]):
            for x0, y0, x1, y1 in meta["panels"]:
                assert box[2] <= x0 or box[0] >= x1 or box[3] <= y0 or box[1] >= y1, (box, meta["panels"])


def test_every_gif_frame_carries_the_guides(shear_snapshots, tmp_path):
    meta = render_animation(shear_snapshots["shear"], tmp_path / "shear.gif", RenderOptions())
    bar = meta["guides"]["scale_bar"]
    with Image.open(tmp_path / "shear.gif") as gif:
        for i in range(gif.n_frames):
            gif.seek(i)
            frame = np.asarray(gif.convert("RGB"), dtype=float)
            bx0, by0, bx1, by1 = bar["box"]
            assert dark_run(frame, (by0 + by1) / 2, bx0, bx1) == pytest.approx(bar["pixels"], abs=2)
