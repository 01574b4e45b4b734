"""The picture around the renders: panels cropped to the specimen, titled, and one colour bar
drawn by matplotlib (so its labels are set in points and read at the report's width, like the
plots), or, for a uniform field, one swatch with the value stated.

Panels are cropped to the union of their non-background pixels, so one camera (one scale) still
holds across panels. Long specimens (cropped width > 1.6 × height) are stacked in one column,
others side by side. Each title is wrapped at word boundaries to its panel's width (measured in
points with the font's metrics; a word wider than the panel lowers the font size, down to
TITLE_MIN_PT), and the title band is as tall as the longest title: six models side by side have
narrow panels, and unwrapped titles ran into their neighbours. Returns each panel's pixel box in
the PNG (x0, y0, x1, y1; origin top left) so tests and readers can find the specimen. The foot row
holds the colour bar between the axis triad (left) and the scale bar (right) of
vlab.render.guides, outside every panel.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab.render.guides import guides, side_width

FIG_WIDTH_IN, DPI = 12.4, 100  # 1240 px: the report page's width
TITLE_PT, TITLE_MIN_PT = 11.0, 7.0
LINE_SPACING = 1.25  # title line height / font size
BACKGROUND_LEVEL = 250  # a pixel whose three channels are all above this is background (white)


def crop_box(images: list[np.ndarray], pad: int = 8) -> tuple[int, int, int, int]:
    """(r0, r1, c0, c1): the union of the images' non-background pixels, padded."""
    mask = np.zeros(images[0].shape[:2], dtype=bool)
    for image in images:
        mask |= (image[..., :3] < BACKGROUND_LEVEL).any(axis=-1)
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    if rows.size == 0:
        return 0, mask.shape[0], 0, mask.shape[1]
    return (max(rows[0] - pad, 0), min(rows[-1] + 1 + pad, mask.shape[0]),
            max(cols[0] - pad, 0), min(cols[-1] + 1 + pad, mask.shape[1]))


def _text_width_pt(text: str, size: float) -> float:
    """Width of ``text`` set in the default font at ``size`` points, in points."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextToPath

    return TextToPath().get_text_width_height_descent(text, FontProperties(size=size), ismath=False)[0]


def _words(line: str) -> list[str]:
    """The line's break points: spaces, except before a number (it stays with what it measures)."""
    words: list[str] = []
    for word in line.split(" "):
        if words and word[:1] and word[0] in "0123456789+-−.":
            words[-1] += " " + word
        else:
            words.append(word)
    return words


def wrap_title(title: str, width_pt: float) -> tuple[str, float]:
    """(title with line breaks, font size) so that no line is wider than ``width_pt`` points: its
    lines wrapped greedily at spaces at TITLE_PT, or at a smaller size where a word alone is wider."""
    size = TITLE_PT
    while True:
        lines = []
        for line in title.split("\n"):
            current = ""
            for word in _words(line):
                trial = f"{current} {word}" if current else word
                if current and _text_width_pt(trial, size) > width_pt:
                    lines.append(current)
                    current = word
                else:
                    current = trial
            lines.append(current)
        if size <= TITLE_MIN_PT or all(_text_width_pt(ln, size) <= width_pt for ln in lines):
            return "\n".join(lines), size
        size = max(size - 1.0, TITLE_MIN_PT)


def _layout(n: int, aspect: float) -> tuple[int, int]:
    """(rows, columns) of n panels whose width/height is ``aspect``."""
    return (n, 1) if aspect > 1.6 and n > 1 else (1, n)


def compose(images: list[np.ndarray], titles: list[str], path: Path, bar: dict, camera) -> dict:
    """Write the PNG; ``bar``: label, clim, cmap, and ``uniform`` (None or the one value) with its
    ``uniform_text``; ``camera`` the one all ``images`` were rendered with. Returns the panel boxes
    in pixels (``panels``) and the guides drawn (``guides``: triad and scale bar)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    r0, r1, c0, c1 = crop_box(images)
    crops = [im[r0:r1, c0:c1] for im in images]
    aspect = (c1 - c0) / max(r1 - r0, 1)
    rows, cols = _layout(len(crops), aspect)
    gap, bar_h, side = 0.15, 1.0, 0.2  # inches
    panel_w = (FIG_WIDTH_IN - 2 * side - (cols - 1) * gap) / cols
    panel_h = min(panel_w / aspect, 5.0)
    panel_w = min(panel_w, panel_h * aspect)
    wrapped = [wrap_title(t, panel_w * 72.0) for t in titles]
    # the band holds the tallest title (lines × line height) and the axes' title pad
    title_h = max(0.6, max(t.count("\n") + 1 for t, _ in wrapped) * TITLE_PT * LINE_SPACING / 72.0 + 0.2)
    height = rows * (panel_h + title_h) + bar_h + 0.1
    fig = Figure(figsize=(FIG_WIDTH_IN, height), dpi=DPI)
    FigureCanvasAgg(fig)
    boxes = []
    try:
        x_free = FIG_WIDTH_IN - cols * panel_w - (cols - 1) * gap
        for i, (crop, (title, size)) in enumerate(zip(crops, wrapped)):
            row, col = divmod(i, cols)
            x = x_free / 2 + col * (panel_w + gap)
            y = height - (row + 1) * (panel_h + title_h)
            ax = fig.add_axes([x / FIG_WIDTH_IN, y / height, panel_w / FIG_WIDTH_IN, panel_h / height])
            ax.imshow(crop, interpolation="antialiased")
            ax.set_axis_off()
            ax.set_title(title, fontsize=size, loc="left")
            x0, y0 = int(round(x * DPI)), int(round((height - y - panel_h) * DPI))
            boxes.append([x0, y0, x0 + int(panel_w * DPI), y0 + int(panel_h * DPI)])
        _colour_bar(fig, bar, height, bar_h, side=side_width(panel_w))
        drawn = guides(fig, camera, panel_w * DPI / (c1 - c0), 0.55)
        fig.savefig(path, dpi=DPI, facecolor="white")
    finally:
        fig.clear()
    return {"panels": boxes, "guides": drawn}


def _colour_bar(fig, bar: dict, height: float, bar_h: float, fig_width: float = FIG_WIDTH_IN, side: float = 0.5):
    """The horizontal colour bar (or uniform swatch) centred at the figure's foot, ``side`` inches
    left free on either side (for the guides); returns its axes."""
    import matplotlib as mpl

    width = min(7.0, fig_width - 2 * side)
    rect = [(fig_width - width) / 2 / fig_width, 0.5 / height, width / fig_width, 0.22 / height]
    ax = fig.add_axes(rect)
    cmap = mpl.colormaps[bar["cmap"]]
    if bar.get("uniform") is not None:  # one colour, its value stated (not a round-off colour scale)
        ax.imshow([[0.5]], cmap=cmap, vmin=0.0, vmax=1.0, aspect="auto", extent=(0, 1, 0, 1))
        ax.set_xticks([]), ax.set_yticks([])
        ax.set_xlabel(bar["uniform_text"], fontsize=11)
        return ax
    norm = mpl.colors.Normalize(*bar["clim"])
    cb = fig.colorbar(mpl.cm.ScalarMappable(norm=norm, cmap=cmap), cax=ax, orientation="horizontal")
    cb.formatter = mpl.ticker.ScalarFormatter(useOffset=False)
    cb.formatter.set_powerlimits((-4, 5))
    cb.update_ticks()
    cb.ax.tick_params(labelsize=10)
    cb.set_label(bar["label"], fontsize=11)
    return ax


FRAME_WIDTH_IN = 8.0  # an animation frame: 800 px, shown 1:1 on the report page (which is 1240 px wide)


def compose_frame(crop: np.ndarray, title: str, bar: dict, camera) -> tuple[np.ndarray, list[int], dict]:
    """One animation frame: the cropped render (through ``camera``) under its title and the colour
    bar of ``bar`` (as compose()'s, labels in points) below it, between the guides. Returns the RGB
    pixels, the colour bar's pixel box (x0, y0, x1, y1; origin top left) and the guides drawn."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    title_h, bar_h, side = 0.6, 1.0, 0.2  # inches
    aspect = crop.shape[1] / max(crop.shape[0], 1)
    panel_w = FRAME_WIDTH_IN - 2 * side
    panel_h = min(panel_w / aspect, 5.0)
    height = panel_h + title_h + bar_h + 0.1
    fig = Figure(figsize=(FRAME_WIDTH_IN, height), dpi=DPI)
    canvas = FigureCanvasAgg(fig)
    try:
        ax = fig.add_axes([side / FRAME_WIDTH_IN, (bar_h + 0.1) / height, panel_w / FRAME_WIDTH_IN, panel_h / height])
        ax.imshow(crop, interpolation="antialiased")
        ax.set_axis_off()
        ax.set_title(title, fontsize=12, loc="left")
        shown_w = min(panel_w, panel_h * aspect)  # imshow keeps the crop's aspect inside the axes
        bar_ax = _colour_bar(fig, bar, height, bar_h, FRAME_WIDTH_IN, side=side_width(shown_w))
        drawn = guides(fig, camera, shown_w * DPI / crop.shape[1], 0.55)
        canvas.draw()
        pixels = np.asarray(canvas.buffer_rgba())[..., :3].copy()
        box = bar_ax.get_window_extent()
        rows = pixels.shape[0]
        return pixels, [int(np.ceil(box.x0)), int(np.ceil(rows - box.y1)), int(box.x1), int(rows - box.y0)], drawn
    finally:
        fig.clear()
