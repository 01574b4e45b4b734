import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from PIL import Image

from vlab.render import offscreen
from vlab.render.specimens import RenderOptions, common_range, render_side_by_side

PIXEL_STD_FLOOR = 20.0  # a blank (uniform) picture has 0; the renders here have ~60-80


def _panels(path, boxes):
    """The model panels of a side-by-side render, cut at the pixel boxes the renderer reports."""
    image = np.asarray(Image.open(path).convert("RGB"), dtype=float)
    return [image[y0:y1, x0:x1] for x0, y0, x1, y1 in boxes]


def test_side_by_side_render_is_not_blank_and_shares_one_colour_range(comparison):
    meta = comparison.summary["renders"]["side_by_side"]
    models = meta["models"]
    snapshots = [comparison.by_model[m].snapshot for m in models]
    assert meta["clim"] == pytest.approx(list(common_range(snapshots, "von-mises")))
    lo, hi = meta["clim"]
    for snap in snapshots:  # every panel's values lie inside the one shared range
        assert lo <= snap.fields["von-mises"][-1].min() and snap.fields["von-mises"][-1].max() <= hi
    panels = _panels(comparison.folder / meta["file"], meta["panels"])
    for model, panel in zip(models, panels):
        assert panel.std() > PIXEL_STD_FLOOR, f"{model} panel is blank"


def test_panels_differ_where_the_physics_differs(comparison):
    meta = comparison.summary["renders"]["side_by_side"]
    panels = dict(zip(meta["models"], _panels(comparison.folder / meta["file"], meta["panels"])))
    # linear and Neo-Hookean have different stress (colour) and lateral contraction (shape)
    difference = np.abs(panels["linear"] - panels["neo-hookean"]).mean()
    assert difference > 5.0


def test_same_model_renders_identically(tmp_path, comparison):
    """The comparison above means something: two renders of the same state agree pixel for pixel."""
    snap = comparison.by_model["stvk"].snapshot
    meta = render_side_by_side([snap, snap], tmp_path / "twice.png", RenderOptions(field="J"))
    a, b = _panels(tmp_path / "twice.png", meta["panels"])
    assert np.abs(a - b).mean() < 1.0
    assert a.std() > PIXEL_STD_FLOOR


def _gif_frames(path) -> list[np.ndarray]:
    with Image.open(path) as gif:
        frames = []
        for i in range(gif.n_frames):
            gif.seek(i)
            frames.append(np.asarray(gif.convert("RGB"), dtype=float))
    return frames


def _bar_strip(frame, box, below: int = 40):
    """The colour bar and its tick labels and title underneath (pixels)."""
    x0, y0, x1, y1 = box
    return frame[y0:y1 + below, x0:x1]


def test_gif_has_a_frame_per_level_each_with_the_same_colour_bar(comparison):
    """One frame per recorded level; every frame carries the colour bar (the viridis ramp from its
    dark end on the left to its yellow end on the right, tick labels and title below), and it is
    the same bar, pixel for pixel, in every frame: one fixed range for the whole test."""
    import matplotlib as mpl

    anim = comparison.summary["renders"]["animation"]
    frames = _gif_frames(comparison.folder / anim["file"])
    assert len(frames) == anim["frames"] == comparison.by_model["neo-hookean"].snapshot.n_frames
    assert frames[-1].std() > PIXEL_STD_FLOOR
    x0, y0, x1, y1 = anim["bar_box"]
    viridis = mpl.colormaps["viridis"]
    first = _bar_strip(frames[0], anim["bar_box"])
    for frame in frames:
        row = frame[(y0 + y1) // 2, x0 + 4:x1 - 4]  # the ramp's middle row, inside its frame line
        assert np.abs(row[0] - 255 * np.array(viridis(0.0)[:3])).max() < 30
        assert np.abs(row[-1] - 255 * np.array(viridis(1.0)[:3])).max() < 30
        assert np.ptp(row, axis=0).max() > 150  # a ramp, not one colour
        strip = _bar_strip(frame, anim["bar_box"])
        assert np.array_equal(strip, first)
        labels = strip[y1 - y0 + 5:]
        assert (labels < 100).all(axis=-1).sum() > 50  # dark text: tick labels and the field's name


def test_gif_colour_range_is_the_whole_test_clamped_at_zero(comparison, tmp_path):
    """The range spans every frame (here the largest stress is in the first frame: a per-frame or
    last-frame range would miss it) and a non-negative field starts at 0 even with a round-off
    negative value."""
    import dataclasses

    from vlab.render.specimens import render_animation

    snap = comparison.by_model["neo-hookean"].snapshot
    order = np.array([snap.n_frames - 1, snap.n_frames // 2, 1, 0])  # the loaded end first, unloaded last
    vm = snap.fields["von-mises"][order].copy()
    vm[-1] -= 5e-4  # the unloaded frame with a round-off negative stress
    reversed_snap = dataclasses.replace(
        snap, t=snap.t[order], stretch=snap.stretch[order], displacement=snap.displacement[order],
        fields={"von-mises": vm}, marks={k: (r, c[order]) for k, (r, c) in snap.marks.items()})
    meta = render_animation(reversed_snap, tmp_path / "back.gif", RenderOptions())
    assert meta["frames"] == 4
    assert meta["clim"] == pytest.approx([0.0, float(snap.fields["von-mises"].max())])
    frames = _gif_frames(tmp_path / "back.gif")
    assert all(np.array_equal(_bar_strip(f, meta["bar_box"]), _bar_strip(frames[0], meta["bar_box"]))
               for f in frames)


def test_unknown_field_is_rejected():
    with pytest.raises(ValueError, match="render field 'stress'.*von-mises"):
        RenderOptions(field="stress")


def test_no_display_and_no_gl_library_gives_a_clear_reason(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(offscreen.ctypes.util, "find_library", lambda name: None)
    with pytest.raises(offscreen.RenderUnavailable, match="libEGL.*libOSMesa"):
        offscreen._choose_window()


def test_renders_off_screen_without_display_and_without_console_noise(tmp_path):
    """A fresh process with no DISPLAY renders a picture and prints nothing to stdout or stderr."""
    script = textwrap.dedent(f"""
        import numpy as np
        from vlab.cli import default_scene_path
        from vlab.compare import run_model
        from vlab.render.specimens import render_side_by_side
        from vlab.scene import load_scene, parse_scene, apply_overrides
        scene = load_scene(default_scene_path())
        scene = parse_scene(apply_overrides(scene.source, {{"test.steps": 2, "mesh.size": 5.0}}))
        snap = run_model(scene, "linear").snapshot
        render_side_by_side([snap], {str(tmp_path / "quiet.png")!r})
    """)
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "VTK_DEFAULT_OPENGL_WINDOW")}
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env,
                          cwd=os.path.dirname(os.path.dirname(__file__)), timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "" and proc.stderr == "", (proc.stdout, proc.stderr)
    image = np.asarray(Image.open(tmp_path / "quiet.png").convert("RGB"), dtype=float)
    assert image.std() > PIXEL_STD_FLOOR
