"""Picture of a buckling (or bifurcation) mode: the eigenvector of the lowest eigenvalue of K_ff
at the critical state, drawn on the specimen.

An eigenvector has no amplitude, so the mode is scaled to a visible peak (``peak_fraction`` of
the specimen's largest dimension) and added to the state at the last stable level; it is coloured
by the magnitude of the (unit) mode at each vertex, so the regions that move most are bright. The
undeformed outline is drawn in grey; the label gives the kind and the bracketed critical strain.
Under the render, at its pixel scale, the axis triad and the scale bar (vlab.render.guides).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab.render.offscreen import setup
from vlab.render.camera import apply_camera, fit_camera
from vlab.render.compose import DPI
from vlab.render.guides import guides
from vlab.render.specimens import _outline

FOOT_IN = 0.9  # inches under the render for the guides


def render_mode(mesh, base: np.ndarray, mode: np.ndarray, path: Path, label: str,
                peak_fraction: float = 0.15, size: tuple[int, int] = (900, 520)) -> dict:
    """PNG of the specimen ``mesh`` displaced by ``base`` (mm, full DOF vector) plus the scaled
    ``mode``; returns what it drew (scale factor, file name, camera, guides)."""
    import pyvista as pv

    from vlab.post.vtu import reference_grid

    setup()
    n = mesh.p.shape[1]
    X = mesh.p.T
    modes = mode.reshape(-1, 3)[:n]
    peak = float(np.max(np.linalg.norm(modes, axis=1), initial=0.0)) or 1.0
    scale = peak_fraction * float(np.ptp(X, axis=0).max()) / peak
    reference = reference_grid(mesh)
    deformed = reference.copy()
    deformed.points = X + base.reshape(-1, 3)[:n] + scale * modes
    deformed.point_data["mode"] = np.linalg.norm(modes, axis=1) / peak
    plotter = pv.Plotter(off_screen=True, window_size=size, border=False)
    try:
        plotter.set_background("white")
        plotter.add_mesh(_outline(reference), color="#737373", line_width=1.5)
        plotter.add_mesh(deformed, scalars="mode", cmap="plasma", clim=(0.0, 1.0), show_edges=True,
                         edge_color="#404040", line_width=0.4, ambient=0.35, diffuse=0.7,
                         scalar_bar_args={"title": "rel. mode", "color": "black", "fmt": "%.2g",
                                          "vertical": True, "position_x": 0.84, "position_y": 0.1,
                                          "height": 0.7, "width": 0.06})
        plotter.add_text(label, position=(0.02, 0.82), viewport=True, font_size=11, color="black")
        aspect = size[1] / size[0]  # the fixed window; margin for the label above the specimen
        camera = fit_camera(np.vstack([X, deformed.points]), width=size[0], margin=0.45,
                            min_aspect=aspect, max_aspect=aspect, reserve_right=0.2)
        apply_camera(plotter, camera)
        image = np.asarray(plotter.screenshot(return_img=True))
    finally:
        plotter.close()
    drawn = _with_guides(image, camera, Path(path))
    return {"file": Path(path).name, "scale": scale, "peak_fraction": peak_fraction,
            "camera": camera.as_dict(), "guides": drawn}


def _with_guides(image: np.ndarray, camera, path: Path) -> dict:
    """Write ``image`` 1:1 (one figure pixel per render pixel) above a foot holding the guides."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    rows, cols = image.shape[:2]
    width, height = cols / DPI, rows / DPI + FOOT_IN
    fig = Figure(figsize=(width, height), dpi=DPI)
    FigureCanvasAgg(fig)
    try:
        ax = fig.add_axes([0.0, FOOT_IN / height, 1.0, rows / DPI / height])
        ax.imshow(image, interpolation="nearest")
        ax.set_axis_off()
        drawn = guides(fig, camera, 1.0, FOOT_IN / 2)
        fig.savefig(path, dpi=DPI, facecolor="white")
    finally:
        fig.clear()
    return drawn
