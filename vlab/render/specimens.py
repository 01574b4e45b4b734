"""Pictures of deformed specimens: models side by side, and an animation of one test.

Every panel of a picture uses the same camera (framing the union of all deformed shapes) and the
same colour range (the union of the field's range over all panels), so sizes and colours compare
directly. Each panel shows the deformed mesh coloured by the chosen cell field, the undeformed
outline in grey, the gauge marks (extensometer, transverse, thickness) as coloured points on
the deformed body, the specimen's rigid plates (a shear test's) in grey, moved with the
vertices bonded to them, and the test's fixtures (vlab.geometry.fixtures: a confined-compression
die see-through in blue-grey, its platens in grey). The camera looks along the specimen's own view where it has one (the
shear layers face-on). One scalar bar, titled with the field and its unit, serves all panels;
the axis triad and the scale bar sit beside it (vlab.render.guides).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vlab.post.fields import FIELDS
from vlab.post.snapshot import Snapshot
from vlab.render.camera import apply_camera, fit_camera
from vlab.render.offscreen import setup

PLATE_COLOUR = "#a6a6a6"
MARK_COLOURS = {"extensometer x": "red", "extensometer y": "magenta", "transverse": "orange",
                "thickness": "deepskyblue"}


@dataclass(frozen=True)
class RenderOptions:
    field: str = "von-mises"
    panel_size: tuple[int, int] = (440, 440)  # pixels per panel
    cmap: str = "viridis"
    frame: int | None = None  # which snapshot frame; None: the state below
    state: str = "peak"  # "peak" (the test's largest stretch, or its end) | "end"
    width: int = 1200  # pixels of each panel's render before cropping

    def __post_init__(self):
        if self.state not in ("peak", "end"):
            raise ValueError(f"render state {self.state!r} unknown; allowed: peak, end")
        if self.field not in FIELDS:
            raise ValueError(f"render field {self.field!r} unknown; allowed: {', '.join(FIELDS)}")


def field_title(field: str) -> str:
    label, unit = FIELDS[field]
    return f"{label} [{unit}]"


NON_NEGATIVE = {"von-mises", "max-stretch", "J", "max-shear"}  # fields whose colour scale never goes below 0
UNIFORM_RTOL = 1e-6  # a spread below this fraction of the field's magnitude is round-off: one colour


def common_range(snapshots: list[Snapshot], field: str, frames=None) -> tuple[float, float]:
    """Smallest and largest cell value of ``field`` over the given frames (one per snapshot, or
    one index/slice for all) of all snapshots; clamped at 0 for a non-negative field."""
    per = frames if isinstance(frames, (list, tuple)) else [frames if frames is not None else -1] * len(snapshots)
    values = [s.fields[field][f] for s, f in zip(snapshots, per)]
    lo, hi = float(min(np.min(v) for v in values)), float(max(np.max(v) for v in values))
    magnitude = max(float(np.abs(s.fields[field]).max()) for s in snapshots)
    if uniform_value(lo, hi, scale=magnitude) is not None:
        lo, hi = lo - 0.5 * max(abs(lo), 1e-3), hi + 0.5 * max(abs(hi), 1e-3)
    if field in NON_NEGATIVE:
        lo = max(lo, 0.0)
    return lo, hi


def uniform_value(lo: float, hi: float, rtol: float = UNIFORM_RTOL, scale: float = 0.0) -> float | None:
    """The field's one value when hi − lo ≤ rtol · m, m = max(|lo|, |hi|, ``scale``) (``scale``: the
    field's magnitude over the whole test, so that an unloaded state's 1e−16 noise is uniform 0),
    else None; a value below rtol · m is 0."""
    m = max(abs(lo), abs(hi), scale)
    if hi - lo > rtol * m and m >= 1e-300:
        return None
    value = 0.5 * (lo + hi)
    return 0.0 if abs(value) <= rtol * m else value


@dataclass(frozen=True)
class State:
    """A recorded level worth a picture and what it is ("peak stretch 1.3", "end of test")."""

    frame: int
    title: str


def render_states(snapshot: Snapshot) -> list[State]:
    """The peak of the test (largest distance of the control from rest: |grip stretch − 1|, or
    |γ| in shear) and, if the test came back from it, the end; one state for a monotonic test;
    the last converged level of a test that stopped."""
    s, last, what = snapshot.stretch, snapshot.n_frames - 1, snapshot.control
    rest = snapshot.rest
    if not snapshot.completed:
        return [State(last, f"stopped at {what} {s[last]:.4g} (last converged level)")]
    peak = int(np.argmax(np.abs(s - rest)))
    if abs(s[peak] - s[last]) <= 1e-12 * max(1.0, abs(s[peak])):
        return [State(last, f"end of test, {what} {s[last]:.4g}")]
    return [State(peak, f"peak {'stretch' if rest else what} {s[peak]:.4g}"), State(last, f"end of test, {what} {s[last]:.4g}")]


def _state(snapshot: Snapshot, which: str) -> State:
    states = render_states(snapshot)
    return states[-1] if which == "end" else states[0]


def _camera(points: np.ndarray, width: int = 1200):
    """The fitted camera (kept for callers that render a single view: buckling modes)."""
    return fit_camera(points, width=width)


_apply_camera = apply_camera


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
        self.plates = []
        for lo, hi, _ in snapshot.plates:
            box = pv.Box(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))
            plotter.add_mesh(box, color=PLATE_COLOUR, show_edges=True, edge_color="#595959", line_width=0.8,
                             ambient=0.35, diffuse=0.7)
            self.plates.append((box, box.points.copy()))
        self.fixtures = []
        for fixture in snapshot.fixtures:  # a die see-through, its platens solid
            surface = pv.PolyData(fixture.at(0), faces=np.hstack([np.full((len(fixture.triangles), 1), 3),
                                                                  fixture.triangles]).ravel())
            plotter.add_mesh(surface, color=fixture.colour, opacity=fixture.opacity, ambient=0.35, diffuse=0.7,
                             smooth_shading=fixture.opacity < 1.0)
            self.fixtures.append((surface, fixture))
        self.marks = {}
        for name, (_, current) in snapshot.marks.items():
            cloud = pv.PolyData(current[0].copy())
            plotter.add_mesh(cloud, color=MARK_COLOURS.get(name, "black"), point_size=16,
                             render_points_as_spheres=True)
            self.marks[name] = cloud

    def show_frame(self, frame: int) -> None:
        s = self.snapshot
        self.deformed.points = self.reference.points + s.displacement[frame]
        self.deformed.cell_data[self.field] = s.fields[self.field][frame]
        for name, cloud in self.marks.items():
            cloud.points = s.marks[name][1][frame]
        for (box, rest), (_, _, moved) in zip(self.plates, s.plates):
            box.points = rest + moved[frame]
        for surface, fixture in self.fixtures:
            surface.points = fixture.at(frame)


def framed_points(snapshot: Snapshot, frames) -> list[np.ndarray]:
    """What the camera must hold of a snapshot at ``frames``: the deformed vertices and the
    vertices of its plates and fixtures, each frame, and the reference vertices."""
    found = [snapshot.points]
    for f in frames:
        found.append(snapshot.points + snapshot.displacement[f])
        found += [part.at(f) for part in snapshot.rigid_parts()]
    return found


def _bar(snapshots: list[Snapshot], field: str, clim, cmap: str, frames) -> dict:
    """What compose draws under the panels: the colour bar of ``clim`` titled with the field and its
    unit, or, when the field's spread over ``frames`` is round-off, one swatch with the value."""
    raw = [s.fields[field][f] for s, f in zip(snapshots, frames)]
    magnitude = max(float(np.abs(s.fields[field]).max()) for s in snapshots)
    uniform = uniform_value(min(float(v.min()) for v in raw), max(float(v.max()) for v in raw), scale=magnitude)
    label, unit = FIELDS[field]
    return {"label": field_title(field), "clim": clim, "cmap": cmap, "uniform": uniform,
            "uniform_text": None if uniform is None else
            f"{label}: uniform, {uniform:.4g}{'' if unit == '1' else ' ' + unit} in every cell "
            f"(spread below {UNIFORM_RTOL:g} of its magnitude)"}


def render_side_by_side(snapshots: list[Snapshot], path: Path, options: RenderOptions = RenderOptions()) -> dict:
    """One PNG with a panel per snapshot at its peak (or end) state, one camera fitted to all of
    them and one colour range; returns what it drew (range, camera, states, panel boxes)."""
    from vlab.render.compose import compose

    field = options.field
    states = [State(options.frame, f"level {options.frame}") if options.frame is not None else
              _state(s, options.state) for s in snapshots]
    frames = [st.frame for st in states]
    clim = common_range(snapshots, field, frames)
    held = [p for s, f in zip(snapshots, frames) for p in framed_points(s, [f])]
    camera = fit_camera(np.vstack(held), width=options.width, view=snapshots[0].view)
    images = [_panel_image(s, f, field, clim, options.cmap, camera) for s, f in zip(snapshots, frames)]
    bar = _bar(snapshots, field, clim, options.cmap, frames)
    titles = [f"{s.model}\n{st.title}" for s, st in zip(snapshots, states)]
    drawn = compose(images, titles, Path(path), bar, camera)
    return {"file": Path(path).name, "field": field, "clim": list(clim), "unit": FIELDS[field][1],
            "models": [s.model for s in snapshots], "frames": frames, "states": [st.title for st in states],
            "uniform": bar["uniform"], "camera": camera.as_dict()} | drawn


def _panel_image(snapshot: Snapshot, frame: int, field: str, clim, cmap: str, camera) -> np.ndarray:
    """The RGB render of one snapshot's frame through ``camera``, on white."""
    import pyvista as pv

    setup()
    plotter = pv.Plotter(off_screen=True, window_size=camera.window, border=False)
    try:
        plotter.set_background("white")
        scene = _Scene(plotter, snapshot, field, clim, cmap)
        scene.show_frame(frame)
        apply_camera(plotter, camera)
        return np.asarray(plotter.screenshot(return_img=True))
    finally:
        plotter.close()


def render_animation(snapshot: Snapshot, path: Path, options: RenderOptions = RenderOptions(),
                     frame_ms: int = 250) -> dict:
    """An animated GIF of one test, unloaded to final level, at a fixed camera and a fixed colour
    range (the field's range over all frames, clamped at 0 for a non-negative field), so that a
    colour means the same value in every frame; each frame carries the colour bar (matplotlib,
    as the side-by-side render's) and its level. All frames share one palette (the last frame's),
    so the bar's pixels are the same in every frame."""
    from PIL import Image

    from vlab.render.compose import compose_frame, crop_box

    field, frames = options.field, list(range(snapshot.n_frames))
    clim = common_range([snapshot], field, slice(None))
    camera = fit_camera(np.vstack(framed_points(snapshot, frames)), width=options.width, view=snapshot.view)
    setup()
    import pyvista as pv

    plotter = pv.Plotter(off_screen=True, window_size=camera.window, border=False)
    renders = []
    try:
        plotter.set_background("white")
        scene = _Scene(plotter, snapshot, field, clim, options.cmap)
        apply_camera(plotter, camera)
        for frame in frames:
            scene.show_frame(frame)
            plotter.render()
            renders.append(np.asarray(plotter.screenshot(return_img=True)))
    finally:
        plotter.close()
    r0, r1, c0, c1 = crop_box(renders)  # one crop for all frames: the specimen does not jump
    bar = _bar([snapshot] * len(frames), field, clim, options.cmap, frames)
    composed = [compose_frame(im[r0:r1, c0:c1], f"{snapshot.model}: {snapshot.control} {snapshot.stretch[f]:.4f}",
                              bar, camera) for im, f in zip(renders, frames)]
    palette = Image.fromarray(composed[-1][0]).quantize(256, dither=Image.Dither.NONE)
    images = [Image.fromarray(px).quantize(palette=palette, dither=Image.Dither.NONE) for px, _, _ in composed]
    images[0].save(path, save_all=True, append_images=images[1:], duration=frame_ms, loop=0)
    return {"file": Path(path).name, "field": field, "clim": list(clim), "model": snapshot.model,
            "frames": len(images), "bar_box": composed[0][1], "uniform": bar["uniform"], "guides": composed[0][2]}
