"""Writes a report folder through vlab.report.folder (atomic, manifest, never replaces a folder vlab did
not make), so a crash or bad input never leaves half a report.

Layout of ``reports/<scene>/`` (one model: the model's files sit in the folder itself):
    index.html                 the page (images inlined with ``single_file``)
    stress_strain.png          all models' curves, analytic dashed, fit window, departures
    lateral_strain.png         lateral vs axial strain and the apparent Poisson's ratio
    render_<field>.png         deformed specimens side by side (when rendering is possible)
    animation_<model>.gif      optional
    comparison.json            departures from Neo-Hookean, render ranges, file list
    scene.toml                 the scene file as run
    <model>/results.json, <model>/curve.csv, <model>/<model>.pvd + <model>/vtu/*.vtu
"""

from __future__ import annotations

import csv
import datetime as _dt
import json
import logging
import os
from dataclasses import dataclass, replace
from pathlib import Path

from vlab.report.folder import report_folder
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the solver is imported only by the writers that need it (vlab fit needs none of it)
    from vlab.report.figure_worker import FigureWorker
    from vlab.run import RunResult

log = logging.getLogger(__name__)


def write_columns_csv(columns: dict[str, list], path: Path) -> None:
    """One column per curve quantity, one row per recorded level ('units' entries are skipped)."""
    cols = {k: v for k, v in columns.items() if k != "units"}
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(cols)
        writer.writerows(zip(*cols.values()))


def write_curve_csv(result: RunResult, path: Path) -> None:
    from vlab.report.results import curve_columns

    write_columns_csv(curve_columns(result), path)


@dataclass(frozen=True)
class ReportOptions:
    true_measures: bool = False  # stress–strain in true instead of engineering measures
    field: str | None = None  # render colouring: von-mises | max-stretch | J | max-shear; None: the kind's
    single_file: bool = False  # images inlined in index.html as base64
    gif_model: str | None = None  # animate this model's test
    render: bool = True  # 3D renders (skipped with a note where the machine cannot render)
    vtu: bool = True  # VTU + PVD time series per model


def write_run(result: RunResult, out: Path, scene_text: str | None = None,
              options: ReportOptions = ReportOptions(), worker: FigureWorker | None = None) -> dict:
    """The report of a single run; returns its results dict."""
    from vlab.report.outcome import outcome_of

    outcome = outcome_of(result, snapshot_now=False)  # taken while the figures are drawn
    write_report([outcome], out, result.scene, scene_text, options, worker)
    return outcome.data


def write_report(outcomes: list, out: Path, scene, scene_text: str | None,
                 options: ReportOptions = ReportOptions(), worker: FigureWorker | None = None) -> dict:
    """Write the report of one scene run with one or more models; returns comparison.json's dict.

    The matplotlib figures are drawn by ``worker`` (vlab.report.figure_worker) while this process
    writes the model files, renders and page, or here when there is none."""
    from vlab.report.figure_worker import figure_job, start_figures
    from vlab.report.html import ReportPage, write_comparison
    from vlab.report.kind_rows import kind_of_data

    single = len(outcomes) == 1
    if options.gif_model is not None and options.gif_model not in [o.model for o in outcomes]:
        raise ValueError(f"gif model {options.gif_model!r} is not among the models run: "
                         f"{', '.join(o.model for o in outcomes)}")
    datas = [o.data for o in outcomes]
    test_kind = kind_of_data(datas[0])
    options = replace(options, field=options.field or test_kind.render_field)  # None: the kind's colouring
    departures = comparison_departures(outcomes)
    kind = "true" if options.true_measures else "engineering"
    job = figure_job(datas, options.true_measures, departures, test_kind.lateral_ratio)
    with report_folder(out, "run" if single else "compare") as tmp:
        drawing = start_figures(job | {"folder": str(tmp)}, worker)
        try:
            links, rendered, renders, notes, view = _beside_figures(outcomes, tmp, scene.name, options,
                                                                    shared_root(out))
        except BaseException:
            drawing.cancel()  # before the folder is discarded: the worker writes into it
            raise
        figures = drawing.result() + rendered
        if scene_text is not None:
            (tmp / "scene.toml").write_text(scene_text, encoding="utf-8")
        summary = {"models": [o.model for o in outcomes], "departures_from_neo_hookean": departures,
                   "renders": renders, "files": links, "measures": kind, "view3d": view}
        (tmp / "comparison.json").write_text(json.dumps(summary, indent=2))
        page = ReportPage(title=scene.name, models=datas, checks={o.model: o.checks for o in outcomes},
                          departures=departures, figures=figures, links=links,
                          provenance=_provenance(scene, scene_text, outcomes), notes=notes,
                          view3d=view["file"] if view else None, sections=_dic_sections(outcomes, tmp, options.single_file))
        write_comparison(page, tmp, inline_images=options.single_file)
    return summary


def _dic_sections(outcomes: list, folder: Path, inline: bool) -> list[str]:
    """The DIC section of each outcome that has one (vlab.report.dic_report), its maps inlined
    in a single-file report."""
    if all(o.dic is None for o in outcomes):
        return []
    from vlab.report.dic_report import html_section
    from vlab.report.html import _image_source

    single = len(outcomes) == 1
    return [html_section(o.data, "" if single else f"{o.model}/", lambda name: _image_source(folder, name, inline))
            for o in outcomes if o.dic is not None]


def _beside_figures(outcomes: list, tmp: Path, title: str, options: ReportOptions, shared: Path | None) -> tuple:
    """What is written while the figures are drawn: the model files, renders and 3-D view;
    (links, render figures, renders, notes, view)."""
    single = len(outcomes) == 1
    links = {o.model: _write_model_files(o, tmp, "." if single else o.model, options) for o in outcomes}
    rendered: list = []
    renders, notes = _renders(outcomes, tmp, options, rendered)
    return links, rendered, renders, notes, _interactive(outcomes, tmp, title, options, shared)


def comparison_departures(outcomes: list) -> dict:
    """comparison.json's ``departures_from_neo_hookean``: where each model's stress first departs
    from Neo-Hookean's, for several models of a kind with a lateral ratio ({} otherwise)."""
    from vlab.report.kind_rows import kind_of_data

    if len(outcomes) == 1 or not kind_of_data(outcomes[0].data).lateral_ratio:
        return {}
    return _departures(outcomes)


def _departures(outcomes: list) -> dict:
    """Where each model's stress first departs from Neo-Hookean's (a comparison that runs it)."""
    from vlab.measure.departure import REFERENCE_MODEL, departure_strains

    by_model = {o.model: o for o in outcomes}
    if REFERENCE_MODEL not in by_model:
        return {}
    ref = by_model[REFERENCE_MODEL].data
    return {o.model: departure_strains(ref, o.data) for o in outcomes if o.model != REFERENCE_MODEL}


def _write_model_files(outcome, root: Path, sub: str, options: ReportOptions) -> list[str]:
    from vlab.post.vtu import write_time_series

    folder = root / sub
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "results.json").write_text(json.dumps(outcome.data, indent=2))
    write_columns_csv(outcome.data["curve"], folder / "curve.csv")
    files = ["results.json", "curve.csv"]
    if outcome.dic is not None:  # [instruments.dic]: images, fields, levels.csv, dic.json, maps
        from vlab.report.dic_report import write_folder

        files += write_folder(outcome.data, outcome.dic, folder)
    if options.vtu:
        pvd = write_time_series(outcome.snapshot, folder, outcome.model)
        files.append(pvd.name)
    return [str(Path(sub) / f) if sub != "." else f for f in files]


def _renders(outcomes, tmp: Path, options: ReportOptions, figures: list) -> tuple[dict, list[str]]:
    """Side-by-side render and optional GIF; a machine that cannot render gets a note instead."""
    from vlab.report.html import Figure

    if not options.render:
        return {}, []
    from vlab.render.offscreen import RenderUnavailable
    from vlab.render.specimens import RenderOptions, render_animation, render_side_by_side, render_states

    ropts = RenderOptions(field=options.field)
    try:
        meta = render_side_by_side([o.snapshot for o in outcomes], tmp / f"render_{options.field}.png", ropts)
        snap = outcomes[0].snapshot
        peak = snap.control.split(" (")[0]  # "twist (rad/mm)": the quantity's name
        figures.append(Figure(meta["file"], _render_caption(meta, f"at its peak ({peak} farthest from rest) or, for a "
                                                            "monotonic test, at its end", snap)))
        renders = {"side_by_side": meta}
        if any(len(render_states(o.snapshot)) > 1 for o in outcomes):  # the test came back from its peak
            end = render_side_by_side([o.snapshot for o in outcomes], tmp / f"render_{options.field}_end.png",
                                      RenderOptions(field=options.field, state="end"))
            figures.append(Figure(end["file"], _render_caption(end, "at the end of the test", snap)))
            renders["end"] = end
        if options.gif_model:
            snap = {o.model: o.snapshot for o in outcomes}[options.gif_model]
            gif = render_animation(snap, tmp / f"animation_{options.gif_model}.gif", ropts)
            figures.append(Figure(gif["file"], f"The {options.gif_model} test from unloaded to the last level."))
            renders["animation"] = gif
        renders |= _critical_modes(outcomes, tmp, figures)
        return renders, []
    except RenderUnavailable as exc:
        log.warning("3D renders skipped: %s", exc)
        return {"skipped": str(exc)}, [f"3D renders skipped: {exc}"]


def shared_root(out) -> Path | None:
    """Where the report's shared files go (vlab.report.shared): the folder holding the report
    folder, whose ``_assets/`` its sibling reports share; None for a report named ``_assets``."""
    from vlab.report.folder import destination
    from vlab.report.shared import ASSETS

    target = Path(os.path.abspath(destination(out).path))
    return None if target.name == ASSETS else target.parent


def _interactive(outcomes, tmp: Path, title: str, options: ReportOptions, shared: Path | None) -> dict | None:
    """view3d.html: the deformed specimens in the reader's browser (rotate, zoom, field, level),
    plotly.js shared with the other reports in ``shared``/_assets/ where it can be."""
    if not options.render:
        return None
    from vlab.report.interactive import write_view

    return write_view([o.snapshot for o in outcomes], tmp, title, inline=options.single_file,
                      shared_root=shared, field=options.field)


GUIDES_CAPTION = ("Lower left: the scene's axes as the camera sees them (x red, y green, z blue; ⊙ towards the "
                  "reader); lower right: a scale bar.")


FIXTURE_WORDS = {"plate": "grey blocks: the rigid plates", "die": "see-through blue-grey: the rigid die",
                 "fixed platen": "grey discs or plates: the platens (the one on the right moves)"}
FIELD_WORDS = {"max-shear": " (in simple shear the amount of shear γ: on a twisted cylinder's surface the "
                            "surface shear twist × radius)"}


def _render_caption(meta: dict, when: str, snapshot=None) -> str:
    """The render's caption: when, the field and its range (what it means where that is not
    plain), the outline, the marks and the rigid parts drawn (``snapshot``'s plates and fixtures)."""
    from vlab.render.specimens import field_title

    lo, hi = meta["clim"]
    scale = (f"uniform field, {meta['uniform']:.4g} in every cell" if meta["uniform"] is not None
             else f"{lo:.4g} to {hi:.4g}")
    names = [] if snapshot is None else list(dict.fromkeys(p.name for p in snapshot.rigid_parts()))
    parts = "".join(f"; {FIXTURE_WORDS[n]}" for n in names if n in FIXTURE_WORDS)
    return (f"Deformed specimens {when}; one camera and one colour scale for all panels "
            f"({field_title(meta['field'])}{FIELD_WORDS.get(meta['field'], '')}: {scale}); grey: undeformed "
            f"outline; points: extensometer (red, magenta), transverse (orange) and thickness (blue) gauge "
            f"marks{parts}. {GUIDES_CAPTION}")


def _critical_modes(outcomes, tmp: Path, figures: list) -> dict:
    """A render of each model's critical mode (first loss of stability: buckling or not)."""
    from vlab.render.mode import render_mode
    from vlab.report.html import Figure

    drawn = {}
    for o in outcomes:
        critical = o.data.get("critical")
        if o.critical_mode is None or critical is None:
            continue
        lo, hi = critical["strain_bracket"]
        name = f"critical_mode_{o.model}.png"
        drawn[f"critical_mode_{o.model}"] = render_mode(
            o.snapshot.mesh, o.snapshot.displacement[-1], o.critical_mode, tmp / name,
            f"{o.model}: {critical['kind']}\ncritical grip strain {lo:.4g} .. {hi:.4g}")
        figures.append(Figure(name, f"{o.model}: mode of the first loss of stability ({critical['kind']}), the "
                              f"eigenvector of the lowest eigenvalue of K_ff, scaled for visibility and added "
                              f"to the last stable state; grey: undeformed outline. {GUIDES_CAPTION}"))
    return drawn


def _provenance(scene, scene_text: str | None, outcomes) -> dict:
    from vlab import __version__

    models = [o.model for o in outcomes]
    override = ("" if models == [scene.material.model] else
                f" · material.model set to each of {', '.join(models)} (scene file says "
                f"{scene.material.model!r})")
    text = scene_text if scene_text is not None else json.dumps(scene.source, indent=2)
    return {"vlab_version": __version__, "scene_hash": scene.content_hash(), "scene_text": text,
            "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "description": scene.description, "override_note": override}
