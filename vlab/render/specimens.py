"""Pictures of deformed specimens: models side by side, and an animation of one test.

Every panel of a picture uses the same camera (framing the union of all deformed shapes) and the
same colour range (the union of the field's range over all panels), so sizes and colours compare
directly. Each panel shows the deformed mesh coloured by the chosen cell field, the undeformed
outline in grey and the gauge marks (extensometer, transverse, thickness) as coloured points on
the deformed body. One scalar bar, titled with the field and its unit, serves all panels.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vlab.post.fields import FIELDS
from vlab.post.snapshot import Snapshot
from vlab.render.offscreen import setup

MARK_COLOURS = {"extensometer x": "red", "extensometer y": "magenta", "transverse": "orange",
                "thickness": "deepskyblue"}
VIEW_DIRECTION = np.array([0.55, -1.0, 0.75])  # from the front-right, above: x runs left to right


@dataclass(frozen=True)
class RenderOptions:
    field: str = "von-mises"
    panel_size: tuple[int, int] = (440, 440)  # pixels per panel
    cmap: str = "viridis"
    frame: int = -1  # which snapshot frame (default: the last recorded level)

    def __post_init__(self):
        if self.field not in FIELDS:
            raise ValueError(f"render field {self.field!r} unknown; allowed: {', '.join(FIELDS)}")


def field_title(field: str) -> str:
    label, unit = FIELDS[field]
    return f"{label} [{unit}]"


def _bar_title(field: str, width: int = 14) -> str:
    """Scalar bar title with its unit, wrapped into lines of at most ``width`` characters."""
    lines: list[str] = []
    for word in field_title(field).split():
        if lines and len(lines[-1]) + 1 + len(word) <= width:
            lines[-1] += " " + word
        else:
            lines.append(word)
    return "\n".join(lines)


def common_range(snapshots: list[Snapshot], field: str, frames=None) -> tuple[float, float]:
    """Smallest and largest cell value of ``field`` over the given frames of all snapshots."""
    values = [s.fields[field][frames if frames is not None else -1] for s in snapshots]
    lo, hi = float(min(np.min(v) for v in values)), float(max(np.max(v) for v in values))
    if hi - lo < 1e-12 * max(1.0, abs(hi)):
        lo, hi = lo - 0.5 * max(abs(lo), 1e-3), hi + 0.5 * max(abs(hi), 1e-3)
    return lo, hi


def _camera(points: np.ndarray) -> dict:
    """Parallel camera framing ``points``: from the front-right above for a solid, straight from
    above (x to the right, y up) for a flat sheet (all z equal)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, radius = (lo + hi) / 2, 0.5 * float(np.linalg.norm(hi - lo))
    if hi[2] - lo[2] <= 1e-12 * max(radius, 1e-300):
        direction, up = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
    else:
        direction = VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION)
        up = np.array([0.0, 0.0, 1.0]) - direction[2] * direction  # screen "up" in world coordinates
    focal = centre + 0.3 * radius * up / np.linalg.norm(up)  # leaves room for the label on top
    viewup = (0.0, 1.0, 0.0) if direction[2] == 1.0 else (0.0, 0.0, 1.0)
    return {"position": tuple(focal + 4.0 * radius * direction), "focal_point": tuple(focal),
            "viewup": viewup, "parallel_scale": 1.3 * radius}


def _apply_camera(plotter, camera: dict) -> None:
    plotter.enable_parallel_projection()
    plotter.camera.position = camera["position"]
    plotter.camera.focal_point = camera["focal_point"]
    plotter.camera.up = camera["viewup"]
    plotter.camera.parallel_scale = camera["parallel_scale"]


def _outline(grid):
    """Edges where the undeformed surface bends by more than 30°: the specimen's silhouette lines.
    The surface's faces are first oriented consistently, or coplanar faces of opposite winding
    would count as a fold and every surface triangle edge would be drawn."""
    if np.ptp(grid.points[:, 2]) == 0.0:  # a flat sheet: its boundary is its silhouette
        return grid.extract_surface(algorithm="dataset_surface").extract_feature_edges(
            boundary_edges=True, feature_edges=False, non_manifold_edges=False, manifold_edges=False)
    surface = grid.extract_surface(algorithm="dataset_surface").compute_normals(
        cell_normals=True, point_normals=False, consistent_normals=True, auto_orient_normals=True)
    return surface.extract_feature_edges(feature_angle=30, boundary_edges=True,
                                         non_manifold_edges=False, manifold_edges=False)


class _Scene:
    """The actors of one panel: deformed mesh, undeformed outline, gauge marks."""

    def __init__(self, plotter, snapshot: Snapshot, field: str, clim, cmap: str):
        import pyvista as pv

        from vlab.post.vtu import reference_grid

        self.snapshot, self.field = snapshot, field
        self.reference = reference_grid(snapshot.mesh)
        outline = _outline(self.reference)
        points = self.reference.points
        if np.ptp(points[:, 2]) == 0.0:  # a flat sheet: lift the outline above the coplanar surface
            outline = outline.translate((0.0, 0.0, 1e-3 * float(np.ptp(points, axis=0).max())))
        plotter.add_mesh(outline, color="#737373", line_width=1.5)
        self.deformed = self.reference.copy()
        self.deformed.cell_data[field] = snapshot.fields[field][0]
        self.actor = plotter.add_mesh(self.deformed, scalars=field, clim=clim, cmap=cmap,
                                      show_edges=True, edge_color="#404040", line_width=0.5,
                                      show_scalar_bar=False, ambient=0.35, diffuse=0.7)
        self.marks = {}
        for name, (_, current) in snapshot.marks.items():
            cloud = pv.PolyData(current[0].copy())
            plotter.add_mesh(cloud, color=MARK_COLOURS.get(name, "black"), point_size=11,
                             render_points_as_spheres=True)
            self.marks[name] = cloud

    def show_frame(self, frame: int) -> None:
        s = self.snapshot
        self.deformed.points = self.reference.points + s.displacement[frame]
        self.deformed.cell_data[self.field] = s.fields[self.field][frame]
        for name, cloud in self.marks.items():
            cloud.points = s.marks[name][1][frame]


def _label(snapshot: Snapshot, field: str, frame: int) -> str:
    lo, hi = snapshot.field_range(field, frame)
    unit = FIELDS[field][1]
    unit = "" if unit == "1" else f" {unit}"
    span = f"{lo:.3g}{unit}" if f"{lo:.3g}" == f"{hi:.3g}" else f"{lo:.3g} to {hi:.3g}{unit}"
    stopped = snapshot.t[frame] < 1.0 - 1e-12 and frame in (-1, snapshot.n_frames - 1)
    return (f"{snapshot.model}{' (test stopped)' if stopped else ''}\n"
            f"{snapshot.control} {snapshot.stretch[frame]:.4g}\n{FIELDS[field][0]}\n{span}")


def _add_label(plotter, text: str):
    """Fixed-size text in the panel's top-left corner (viewport coordinates, no auto-scaling)."""
    return plotter.add_text(text, position=(0.03, 0.78), viewport=True, font_size=11, color="black")


def _new_plotter(n_panels: int, panel_size, bar: bool):
    import pyvista as pv

    setup()
    weights = [1.0] * n_panels + ([0.4] if bar else [])
    width = int(panel_size[0] * sum(weights))
    plotter = pv.Plotter(off_screen=True, shape=(1, len(weights)), col_weights=weights,
                         window_size=(width, panel_size[1]), border=False)
    plotter.set_background("white")
    return plotter


def _scalar_bar(plotter, column: int, actor, field: str) -> None:
    plotter.subplot(0, column)
    plotter.add_scalar_bar(title=_bar_title(field), mapper=actor.mapper, vertical=True,
                           color="black", position_x=0.3, position_y=0.08, width=0.3, height=0.72,
                           title_font_size=14, label_font_size=12, n_labels=6, fmt="%.3g")


def render_side_by_side(snapshots: list[Snapshot], path: Path, options: RenderOptions = RenderOptions()) -> dict:
    """One PNG with a panel per snapshot; returns what it drew (range, camera, panel models)."""
    field, frame = options.field, options.frame
    clim = common_range(snapshots, field, frame)
    deformed = [s.points + s.displacement[frame] for s in snapshots]
    camera = _camera(np.vstack(deformed + [snapshots[0].points]))
    plotter = _new_plotter(len(snapshots), options.panel_size, bar=True)
    try:
        for col, snap in enumerate(snapshots):
            plotter.subplot(0, col)
            scene = _Scene(plotter, snap, field, clim, options.cmap)
            scene.show_frame(frame)
            _add_label(plotter, _label(snap, field, frame))
            _apply_camera(plotter, camera)
        _scalar_bar(plotter, len(snapshots), scene.actor, field)
        plotter.screenshot(str(path))
    finally:
        plotter.close()
    return {"file": Path(path).name, "field": field, "clim": list(clim), "unit": FIELDS[field][1],
            "models": [s.model for s in snapshots], "panel_width": options.panel_size[0],
            "frame": frame}


def render_animation(snapshot: Snapshot, path: Path, options: RenderOptions = RenderOptions(),
                     frame_ms: int = 250) -> dict:
    """An animated GIF of one test, unloaded to final level, at a fixed camera and colour range."""
    from PIL import Image

    field = options.field
    frames = list(range(snapshot.n_frames))
    clim = common_range([snapshot], field, slice(None))
    camera = _camera(np.vstack([snapshot.points + u for u in snapshot.displacement]))
    plotter = _new_plotter(1, options.panel_size, bar=True)
    images = []
    try:
        plotter.subplot(0, 0)
        scene = _Scene(plotter, snapshot, field, clim, options.cmap)
        _apply_camera(plotter, camera)
        text = _add_label(plotter, "")
        _scalar_bar(plotter, 1, scene.actor, field)
        for frame in frames:
            plotter.subplot(0, 0)
            scene.show_frame(frame)
            text.input = f"{snapshot.model}\n{snapshot.control} {snapshot.stretch[frame]:.4f}"
            plotter.render()
            images.append(Image.fromarray(plotter.screenshot(return_img=True)))
    finally:
        plotter.close()
    images[0].save(path, save_all=True, append_images=images[1:], duration=frame_ms, loop=0)
    return {"file": Path(path).name, "field": field, "clim": list(clim), "model": snapshot.model,
            "frames": len(images)}
