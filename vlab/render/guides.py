"""The guides drawn beside every render, outside the specimen's panel so they never hide it: an
axis triad (the scene's x, y, z as seen by the camera) and a scale bar (a round length in mm).

Triad: each unit axis e is drawn as the arrow (e·r, e·u) of length ``TRIAD_IN`` inches (r, u the
screen's right and up), red x, green y, blue z; an axis within 12° of the view direction d has
no visible arrow and is drawn as a circled dot (pointing at the viewer, e·d > 0) or a circled cross.

Scale bar: the largest length ℓ in the 1–2–5 series (1, 2, 5, 10, 20, … mm) with ℓ ≤ w/5, w the
specimen's width on screen (mm), drawn ℓ k inches long, k the picture's inches per mm:
k = z / (DPI · m), m the render's mm per pixel (vlab.render.camera.Camera.mm_per_pixel, parallel
projection: the same everywhere) and z the figure pixels per render pixel of the panel.
"""

from __future__ import annotations

import math

import numpy as np

TRIAD_IN = 0.32  # inches: length of an axis arrow seen side-on
AXIS_COLOURS = {"x": "#d62728", "y": "#2ca02c", "z": "#1f77b4"}
END_ON = math.sin(math.radians(12.0))  # projected length below which an axis is drawn end-on
BAR_THICKNESS_PT = 3.0


def round_length(extent: float) -> float:
    """The largest 1–2–5 length (mm) not above ``extent``/5 (at least 1e−3 mm)."""
    target = max(extent / 5.0, 1e-3)
    decade = 10.0 ** math.floor(math.log10(target))
    return max(m * decade for m in (1.0, 2.0, 5.0) if m * decade <= target * (1 + 1e-9))


def triad(fig, centre_in: tuple[float, float], axes: tuple[np.ndarray, np.ndarray, np.ndarray]) -> dict:
    """Draw the triad around ``centre_in`` (figure inches from the lower left); ``axes`` (d, r, u) of
    the camera. Returns each axis' drawn 2-D direction (screen right, up), whether it is end-on,
    and the triad's centre and pixel box (x0, y0, x1, y1; origin top left)."""
    d, r, u = axes
    w, h = fig.get_size_inches()
    span = 2.6 * TRIAD_IN
    ax = fig.add_axes([(centre_in[0] - span / 2) / w, (centre_in[1] - span / 2) / h, span / w, span / h])
    ax.set_xlim(-span / 2, span / 2), ax.set_ylim(-span / 2, span / 2)
    ax.set_axis_off()
    drawn = {}
    for name, e in zip("xyz", np.eye(3)):
        colour = AXIS_COLOURS[name]
        v = np.array([e @ r, e @ u])
        end_on = bool(np.hypot(*v) < END_ON)
        if end_on:
            ax.plot([0.0], [0.0], marker="o", ms=11, mfc="white", mec=colour, mew=1.5, zorder=3)
            ax.plot([0.0], [0.0], marker="." if e @ d > 0 else "x", ms=6, color=colour, zorder=4)
            label_at = np.array([0.14, -0.12])
        else:
            tip = TRIAD_IN * v
            ax.annotate("", xy=tip, xytext=(0.0, 0.0),
                        arrowprops={"arrowstyle": "-|>", "color": colour, "lw": 1.6, "shrinkA": 0, "shrinkB": 0})
            label_at = tip + 0.09 * v / np.hypot(*v)
        ax.text(*label_at, name, color=colour, fontsize=10, ha="center", va="center", fontweight="bold")
        drawn[name] = {"screen": [float(v[0]), float(v[1])], "end_on": end_on,
                       "towards_viewer": bool(e @ d > 0)}
    dpi, (cx, cy) = fig.dpi, centre_in
    drawn["centre"] = [cx * dpi, (h - cy) * dpi]
    drawn["box"] = [(cx - span / 2) * dpi, (h - cy - span / 2) * dpi, (cx + span / 2) * dpi, (h - cy + span / 2) * dpi]
    return drawn


def scale_bar(fig, right_in: float, base_in: float, mm_per_inch: float, extent_mm: float) -> dict:
    """Draw the bar with its right end at (``right_in``, ``base_in``) figure inches, its label above;
    ``mm_per_inch`` the panel's scale, ``extent_mm`` the specimen's width on screen. Returns the
    length (mm), its drawn length (inches and figure pixels) and the bar's pixel box
    (x0, y0, x1, y1; origin top left)."""
    length = round_length(extent_mm)
    size_in = length / mm_per_inch
    left_in = right_in - size_in
    w, h = fig.get_size_inches()
    dpi = fig.dpi
    ax = fig.add_axes([0.0, 0.0, 1.0, 1.0], facecolor="none")
    ax.set_xlim(0.0, w), ax.set_ylim(0.0, h)  # data units: figure inches
    ax.set_axis_off()
    ax.plot([left_in, left_in + size_in], [base_in, base_in], color="black", lw=BAR_THICKNESS_PT,
            solid_capstyle="butt")
    for x in (left_in, left_in + size_in):  # end ticks
        ax.plot([x, x], [base_in - 0.05, base_in + 0.05], color="black", lw=1.0)
    label = ax.text(left_in + size_in / 2, base_in + 0.09, f"{length:g} mm", ha="center", va="bottom", fontsize=10)
    half = BAR_THICKNESS_PT / 72 / 2
    box = [left_in * dpi, (h - base_in - half) * dpi, (left_in + size_in) * dpi, (h - base_in + half) * dpi]
    text = label.get_window_extent(fig.canvas.get_renderer())
    return {"mm": length, "label": label.get_text(), "inches": size_in, "pixels": size_in * dpi,
            "box": [float(b) for b in box],
            "label_box": [float(text.x0), float(h * dpi - text.y1), float(text.x1), float(h * dpi - text.y0)]}


SIDE_IN = 0.3  # inches between a guide and the figure's edge


def side_width(panel_width_in: float) -> float:
    """Inches the guides need on each side of a foot row under a panel ``panel_width_in`` wide: the
    longest scale bar (a fifth of the panel) or the triad, whichever is wider, plus the margin."""
    return SIDE_IN + max(panel_width_in / 5.0, 2.6 * TRIAD_IN)


def guides(fig, camera, zoom: float, height_in: float) -> dict:
    """The triad at the left and the scale bar at the right of the figure, centred ``height_in``
    inches above its foot, for panels showing ``camera``'s render at ``zoom`` figure pixels per
    render pixel. Returns what was drawn (for tests and the JSON)."""
    mm_per_inch = camera.mm_per_pixel * fig.dpi / zoom
    width = fig.get_size_inches()[0]
    bar = scale_bar(fig, width - SIDE_IN, height_in, mm_per_inch, camera.extent[0])
    return {"triad": triad(fig, (SIDE_IN + 1.3 * TRIAD_IN, height_in), camera.axes),
            "scale_bar": bar | {"mm_per_pixel": mm_per_inch / fig.dpi}}
