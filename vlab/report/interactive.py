"""The interactive 3-D view of a report: ``view3d.html`` next to ``index.html``, with plotly.js
(``plotly.min.js`` from the plotly package, no network: one copy shared by the reports of a folder
in ``../_assets/plotly-<version>.min.js`` (vlab.report.shared), else shipped in the report folder,
or inlined in a single-file report) drawing the
deformed specimens as WebGL meshes the reader rotates and zooms, with a field menu, a model menu
and a load-level slider; the gauge marks are points, the undeformed outline grey lines, and the
rigid parts (a shear test's plates, a die and its platens) meshes of their own colour, moved rigidly.

Only the specimen's boundary is sent: its surface triangles (from pyvista's surface filter, each
keeping the index of the volume cell it bounds), the displacement of the surface vertices and the
cell fields of the bounding cells, as base64 float32, at up to ``MAX_LEVELS`` levels (evenly
spaced, always the peak and the last). One colour range per field over all models and levels, so
colours compare across the slider and the menu. Measured sizes: benchmarks/… see the README.
"""

from __future__ import annotations

import base64
import html
import json
import shutil
from pathlib import Path

import numpy as np

from vlab.post.fields import FIELDS
from vlab.post.snapshot import Snapshot

MAX_LEVELS = 30
PLOTLY_JS = "plotly.min.js"
MARK_COLOURS = {"extensometer x": "red", "extensometer y": "magenta", "transverse": "orange",
                "thickness": "deepskyblue"}


def _b64(array: np.ndarray, dtype) -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


def peak_frame(snapshot: Snapshot) -> int:
    """The frame of the largest |control − its rest value| (a stretch's 1, a twist's 0)."""
    return int(np.argmax(np.abs(snapshot.stretch - snapshot.rest)))


def chosen_levels(snapshot: Snapshot, limit: int = MAX_LEVELS) -> list[int]:
    """Up to ``limit`` frames: evenly spaced, with the peak (``peak_frame``) and the last."""
    n = snapshot.n_frames
    keep = set(np.unique(np.linspace(0, n - 1, min(n, limit - 1)).round().astype(int)).tolist())
    keep |= {peak_frame(snapshot), n - 1}
    return sorted(keep)


def fixtures_payload(snapshot: Snapshot, levels: list[int]) -> list[dict]:
    """The rigid parts (plates, a die and its platens: Snapshot.rigid_parts) at ``levels``: each
    surface once, its rigid translation per level."""
    return [{"name": p.name, "X": _b64(p.points, np.float32), "tri": _b64(p.triangles, np.int32),
             "colour": p.colour, "opacity": p.opacity, "move": [[float(v) for v in p.displacement[f]] for f in levels]}
            for p in snapshot.rigid_parts()]


def _surface(snapshot: Snapshot):
    """(vertex ids, triangles into them, bounding cell per triangle, outline segments)."""
    from vlab.post.vtu import reference_grid
    from vlab.render.specimens import _outline

    grid = reference_grid(snapshot.mesh)
    surf = grid.extract_surface(pass_pointid=True, pass_cellid=True, algorithm="dataset_surface").triangulate()
    tri = surf.faces.reshape(-1, 4)[:, 1:]
    vertices = np.asarray(surf.point_data["vtkOriginalPointIds"])
    cells = np.asarray(surf.cell_data["vtkOriginalCellIds"])
    outline = _outline(grid)
    lines = outline.lines.reshape(-1, 3)[:, 1:] if outline.n_lines else np.zeros((0, 2), int)
    segments = outline.points[lines]  # (n, 2, 3)
    return vertices, tri, cells, segments


def model_payload(snapshot: Snapshot) -> dict:
    """What the page needs of one model, arrays base64-encoded (float32, int32)."""
    vertices, tri, cells, segments = _surface(snapshot)
    used_cells, tcell = np.unique(cells, return_inverse=True)
    levels = chosen_levels(snapshot)
    X = snapshot.points[vertices]
    xyz = np.full((len(segments) * 3, 3), np.nan)
    xyz[0::3], xyz[1::3] = segments[:, 0], segments[:, 1]  # NaN rows break the line between segments
    s = snapshot.stretch
    return {
        "name": snapshot.model, "nv": len(vertices), "X": _b64(X, np.float32), "tri": _b64(tri, np.int32),
        "tcell": _b64(tcell, np.int32), "outline": _b64(xyz, np.float32),
        "levels": [f"{snapshot.control} {s[f]:.4g} (level {f} of {snapshot.n_frames - 1})" for f in levels],
        "U": [_b64(snapshot.displacement[f][vertices], np.float32) for f in levels],
        "fields": {name: [_b64(snapshot.fields[name][f][used_cells], np.float32) for f in levels]
                   for name in FIELDS},
        "marks": {name: {"colour": MARK_COLOURS.get(name, "black"),
                         "xyz": [_b64(cur[f], np.float32) for f in levels]}
                  for name, (_, cur) in snapshot.marks.items()},
        "fixtures": fixtures_payload(snapshot, levels),
        "start": levels.index(peak_frame(snapshot)),
    }


def view_box(snapshots: list[Snapshot]) -> dict:
    """plotly's scene box (extents of the specimens and their rigid parts over every level, largest
    1: plotly's "data" mode scales a long specimen past the frame) and the eye: front-right above,
    or straight above a flat sheet."""
    from vlab.render.camera import VIEW_DIRECTION, is_flat

    pts = np.vstack([s.points + u for s in snapshots for u in s.displacement]
                    + [p.at(f) for s in snapshots for p in s.rigid_parts() for f in range(s.n_frames)])
    extent = np.maximum(np.ptp(pts, axis=0), 1e-9 * float(np.ptp(pts, axis=0).max()))
    ratio = extent / extent.max()
    flat = is_flat(np.vstack([s.points for s in snapshots]))
    # plotly fits its unit box to the frame: a long, slender box needs the eye closer (measured on
    # the ISO 527-2 1A dumb-bell, ratios 1 : 0.08 : 0.016, and a 2.5 : 1 : 1 block)
    distance = 0.7 + 1.5 * float(np.sort(ratio)[-2])
    eye = np.array([0.0, -1e-3, 1.6]) if flat else distance * VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION)
    return {"aspect": dict(zip("xyz", map(float, ratio))), "eye": dict(zip("xyz", map(float, eye))),
            "up": {"x": 0, "y": 1, "z": 0} if flat else {"x": 0, "y": 0, "z": 1}}


def field_ranges(snapshots: list[Snapshot]) -> dict:
    """One colour range per field over every model and level (widened if the field is uniform)."""
    from vlab.render.specimens import common_range

    return {name: list(common_range(snapshots, name, slice(None))) for name in FIELDS}


def plotly_source(folder: Path, shared_root: Path | None, inline: bool) -> tuple[str, list[str], str | None]:
    """How the page gets plotly.js: (the script tag, files written into ``folder``, the shared
    copy's path relative to ``folder`` or None). Inlined when ``inline``; else the copy shared in
    ``shared_root/_assets/`` when it can be (vlab.report.shared), else a copy in ``folder``."""
    import plotly

    from vlab.report.shared import share

    src = Path(plotly.__file__).parent / "package_data" / PLOTLY_JS
    if inline:
        return f"<script>{src.read_text(encoding='utf-8')}</script>", [], None
    shared = None if shared_root is None else share(src, shared_root, f"plotly-{plotly.__version__}.min.js")
    if shared is not None:
        return f'<script src="{html.escape(shared)}"></script>', [], shared
    shutil.copyfile(src, folder / PLOTLY_JS)
    return f'<script src="{PLOTLY_JS}"></script>', [PLOTLY_JS], None


def _missing_note(shared: str | None) -> str:
    return (f"plotly.js did not load from {shared}: this report uses the copy its reports folder shares. "
            "Keep the _assets folder beside the report folder when moving it (move or copy both), or "
            "write the report with --single-file to carry its own copy." if shared else
            f"plotly.js did not load ({PLOTLY_JS} is missing from the report folder).")


def write_view(snapshots: list[Snapshot], folder: Path, title: str, inline: bool = False,
               shared_root: Path | None = None, field: str = "von-mises") -> dict:
    """Write ``view3d.html`` (plotly.js as :func:`plotly_source` chooses), opening on ``field``;
    returns what it wrote."""
    import plotly

    folder = Path(folder)
    script, own, shared = plotly_source(folder, shared_root, inline)
    data = {"title": title, "models": [model_payload(s) for s in snapshots], "ranges": field_ranges(snapshots),
            "view": view_box(snapshots), "plotly_missing": _missing_note(shared), "field": field,
            "fields": {k: f"{label} [{unit}]" for k, (label, unit) in FIELDS.items()}}
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    page = (Path(__file__).parent / "assets" / "view3d.html").read_text(encoding="utf-8")
    page = (page.replace("{{TITLE}}", html.escape(title)).replace("{{PLOTLY}}", script)
            .replace("{{DATA}}", payload).replace("{{VIEWER}}",
                                                  (Path(__file__).parent / "assets" / "view3d.js").read_text()))
    (folder / "view3d.html").write_text(page, encoding="utf-8")
    files = ["view3d.html"] + own
    return {"file": "view3d.html", "files": files, "plotly_version": plotly.__version__, "plotly_shared": shared,
            "bytes": {f: (folder / f).stat().st_size for f in files}}
