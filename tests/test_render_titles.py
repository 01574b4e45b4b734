"""Render panel titles stay over their own panel (vlab compare puts six models side by side)."""

from __future__ import annotations

import numpy as np
from matplotlib.image import imread

from vlab.render.camera import fit_camera
from vlab.render.compose import TITLE_MIN_PT, compose, wrap_title, _text_width_pt

BAR = {"label": "von Mises Cauchy stress [MPa]", "clim": (3.6, 7.7), "cmap": "viridis", "uniform": None}


def _block() -> np.ndarray:
    """A grey box on white, 1.4 times as wide as tall, as the cropped render of a stretched block
    with its outline (vlab compare's panels sit side by side below an aspect of 1.6)."""
    image = np.full((300, 400, 3), 255, np.uint8)
    image[60:230, 40:280] = 90
    return image


def _ink_columns_above_panels(path, boxes) -> np.ndarray:
    pixels = imread(str(path))[..., :3]
    band = pixels[: min(b[1] for b in boxes) - 2]  # the title band above the first row of panels
    return np.flatnonzero((band < 0.6).any(axis=2).any(axis=0))


def test_six_long_titles_are_wrapped_inside_their_panels(tmp_path):
    titles = [f"{m}\nend of test, grip stretch 3" for m in
              ("neo-hookean", "mooney-rivlin", "yeoh", "ogden", "gent", "arruda-boyce-with-a-long-label")]
    corners = np.array([[x, y, z] for x in (0.0, 40.0) for y in (0.0, 17.0) for z in (0.0, 5.0)])  # mm
    boxes = compose([_block()] * 6, titles, tmp_path / "r.png", BAR, fit_camera(corners, width=400))["panels"]
    assert len(boxes) == 6 and len({b[1] for b in boxes}) == 1  # one row
    ink = _ink_columns_above_panels(tmp_path / "r.png", boxes)
    assert ink.size > 100  # the titles are there
    inside = np.zeros(ink.shape, bool)
    for x0, _, x1, _ in boxes:
        inside |= (ink >= x0) & (ink <= x1)
    assert inside.all(), f"title ink outside every panel at columns {ink[~inside][:10]}"
    for x0, _, x1, _ in boxes:  # each panel has its own title ink
        assert ((ink >= x0) & (ink <= x1)).sum() > 10


def test_wrap_title_breaks_at_spaces_and_shrinks_only_for_a_word_too_wide():
    text, size = wrap_title("mooney-rivlin\nend of test, grip stretch 3", 120.0)
    assert size == 11.0 and text.startswith("mooney-rivlin\n") and text.count("\n") >= 2
    assert all(_text_width_pt(line, size) <= 120.0 for line in text.split("\n"))
    assert text.replace("\n", " ") == "mooney-rivlin end of test, grip stretch 3"
    wide, small = wrap_title("a-label-without-any-space-in-it", 60.0)
    assert small == TITLE_MIN_PT and wide == "a-label-without-any-space-in-it"
    assert wrap_title("gent", 500.0) == ("gent", 11.0)
    assert "stretch 3" in wrap_title("end of test, grip stretch 3", 100.0)[0]  # a number stays with its word
