"""A one-page HTML summary of a run (the full comparison report builds on the same pieces)."""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

from vlab.report.kind_rows import kind_of_data, kind_rows
from vlab.report.explain import by_design_notes


def _fmt(value, digits: int = 5) -> str:
    if value is None:
        return "—"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return html.escape(str(value))


def _newton_cost(solver: dict) -> str:
    """Iterations, how many of them refactorized, and all factorizations (stability checks too)."""
    text = _fmt(sum(solver["newton_iterations"]))
    if solver.get("exact_iterations") is not None:
        text += (f" ({_fmt(sum(solver['exact_iterations']))} refactorized; {_fmt(solver['factorizations'])} "
                 f"factorizations in all; newton = \"{html.escape(solver.get('newton', ''))}\")")
    return text


def _solvers(solver: dict) -> str:
    """The direct solver (and the Newton corrections' one if different) and the tangent kernel."""
    linear = solver.get("linear") or {}
    text = _fmt(linear.get("direct"))
    if linear.get("newton") not in (None, "direct", linear.get("direct")):
        text += f" (Newton corrections: {_fmt(linear['newton'])})"
    return f"{text}; {_fmt(solver.get('tangent_kernel'))}"


def _why(notes: dict, key: str) -> str:
    """The reason a measured constant differs from its input by design, set under the number."""
    return f"<br><small class=why>{html.escape(notes[key])}</small>" if key in notes else ""


def summary_rows(data: dict) -> list[tuple[str, str]]:
    m, inp, solver, timing, mesh = (data["measured"], data["input"], data["solver"],
                                    data["timing"], data["mesh"])
    kind = kind_of_data(data)
    why = by_design_notes(data)
    force = kind.force_column
    elastic = [
        ("E measured / input [MPa]", f"{_fmt(m['E'])} / {_fmt(inp['E'])}{_why(why, 'E')}"),
        ("ν measured / input", f"{_fmt(m['nu'])} / {_fmt(inp['nu'])}{_why(why, 'nu')}"),
        ("E from crosshead strain [MPa]", _fmt(m.get("E_crosshead"))),
    ] if kind.measures_E else []
    rows = [
        ("model", inp["model"] if inp.get("label", inp["model"]) == inp["model"]
                  else f"{inp['label']} ({inp['model']})"),
        *elastic,
        *((name, cells[0]) for name, cells in kind_rows([data])),
        ("force at last level [N]", _fmt(data["curve"][force][-1] if data["curve"][force] else None)),
        ("Newton iterations (total)", _newton_cost(solver)),
        ("linear solver; tangent kernel", _solvers(solver)),
        ("cutbacks", _fmt(sum(solver["cutbacks"]))),
        ("mesh", f"{mesh['cell']} order {mesh['order']}, {mesh['elements']} elements, {mesh['dofs']} DOFs"
                 + (f", symmetry {mesh['symmetry']}" if mesh.get("symmetry", "none") != "none" else "")),
        ("wall time [s]", _fmt(timing["total_s"], 3)),
    ]
    if m.get("E_fit"):
        rows.append(("E fit", f"{m['E_fit']['method']} over |strain| {m['E_fit']['window']}, "
                              f"{m['E_fit']['n_points']} points, R² = {m['E_fit']['r2']:.6f}"))
    unc = m.get("uncertainty") or {}
    for key, unit in (("E", " [MPa]"), ("nu", "")):
        iv = unc.get(key)
        if iv:  # effects.noise: the interval and the value the exact instruments would read
            rows.append((f"{'ν' if key == 'nu' else 'E'} {100 * iv['confidence']:g} % interval{unit}",
                         f"[{_fmt(iv['low'])}, {_fmt(iv['high'])}] from {iv['n_points']} noisy points; "
                         f"noiseless {_fmt(unc['noiseless'][key])}"))
    stab = data.get("stability") or []
    if stab:
        unstable = [r for r in stab if not r["accepted"]]
        rows.append(("stability (inertia of K_ff)",
                     f"{len(stab) - len(unstable)} of {len(stab)} levels stable (no negative eigenvalue)"
                     + (f"; stopped at stretch {unstable[0]['stretch']}: "
                        f"{unstable[0]['negative_eigenvalues']} negative eigenvalue(s), "
                        f"limit point {unstable[0]['limit_point']}" if unstable else "")))
    rows += cruciform_rows(data.get("cruciform"))
    ref = data.get("reference") or {}
    for k, v in ref.items():
        if k.startswith("max_relative_error"):
            rows.append((f"stress vs analytic ({k[-1]})", f"max relative error {_fmt(v, 3)}"))
    return rows


def cruciform_rows(cruciform: dict | None) -> list[tuple[str, str]]:
    """Nominal vs centre stress and the correction factor, per axis (cruciform runs only)."""
    if not cruciform:
        return []
    rows = []
    for when in ("small_strain", "final"):
        row = cruciform.get(when)
        if not row:
            continue
        for xy in "xy":
            if f"nominal_stress_{xy}" in row:
                rows.append((f"{xy} stress nominal / centre [MPa], {when.replace('_', ' ')}",
                             f"{_fmt(row[f'nominal_stress_{xy}'])} / {_fmt(row[f'centre_stress_{xy}'])} "
                             f"(correction factor {_fmt(row[f'correction_factor_{xy}'], 4)})"))
    rows.append(("E, ν from extensometers and nominal stress",
                 f"{_fmt(cruciform.get('E_nominal'))} MPa, {_fmt(cruciform.get('nu_nominal'))}"))
    return rows


def write_index(data: dict, path: Path, images: list[str]) -> None:
    status = ("<p class=ok>Test completed.</p>" if data["converged"] else
              f"<p class=fail>Test stopped: {html.escape(json.dumps(data['failure']))}</p>")
    rows = "".join(f"<tr><th>{html.escape(k)}</th><td>{v}</td></tr>" for k, v in summary_rows(data))
    imgs = "".join(f'<figure><img src="{html.escape(i)}" alt="{html.escape(i)}"></figure>' for i in images)
    page = f"""<!doctype html><html><head><meta charset="utf-8">
<title>vlab — {html.escape(data['scene']['name'])}</title>
<style>body{{font-family:sans-serif;max-width:60rem;margin:2rem auto;color:#222}}
table{{border-collapse:collapse}}th,td{{border:1px solid #ccc;padding:.3rem .6rem;text-align:left}}
.ok{{color:#060}}.fail{{color:#a00}}img{{max-width:100%}}</style></head><body>
<h1>vlab report: {html.escape(data['scene']['name'])}</h1>{status}
<table>{rows}</table>{imgs}
<p><small>vlab {html.escape(data['vlab_version'])} · {html.escape(data['date'])} · scene hash {html.escape(data['scene']['hash'][:12])}</small></p>
</body></html>"""
    Path(path).write_text(page)


# --- the comparison report (one or more models of one scene) ---------------------------------

import base64  # noqa: E402
import mimetypes  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402

_STYLE = """body{font-family:sans-serif;max-width:78rem;margin:2rem auto;padding:0 1rem;color:#222}
table{border-collapse:collapse;margin:1rem 0}th,td{border:1px solid #ccc;padding:.3rem .6rem;text-align:left}
td.num{text-align:right;font-variant-numeric:tabular-nums}.ok{color:#060}.fail{color:#a00}
figure{margin:1.5rem 0}img{max-width:100%;border:1px solid #eee}figcaption{font-size:.9rem;color:#444}
pre{background:#f6f6f6;padding:.8rem;overflow-x:auto}small{color:#666}"""


@dataclass(frozen=True)
class Figure:
    file: str  # relative to the report folder
    caption: str


@dataclass(frozen=True)
class ReportPage:
    """Everything the comparison page shows; numbers come from the models' results dicts."""

    title: str
    models: list[dict]
    checks: dict[str, dict]
    departures: dict[str, dict]
    figures: list[Figure]
    links: dict[str, list[str]]
    provenance: dict
    notes: list[str] = field(default_factory=list)
    view3d: str | None = None  # the interactive 3-D view's page in the folder


def _model_status(data: dict) -> str:
    if data["converged"]:
        return "<span class=ok>completed</span>"
    f = data["failure"]
    load = kind_of_data(data).load_key
    return (f"<span class=fail>stopped at step {f['step']}, {load} {_fmt(f['stretch'])}: "
            f"{html.escape(f['reason'])}</span>")


def comparison_rows(page: ReportPage) -> list[tuple[str, list[str]]]:
    """(quantity, value per model) rows of the models table, every value as measured."""
    def per(fn):
        return [fn(d) for d in page.models]

    kind = kind_of_data(page.models[0])

    def force(d):
        forces, control = d["curve"][kind.force_column], d["curve"][kind.control_column]
        if not forces:
            return "—"
        rest = 1.0 if kind.load_key == "stretch" else 0.0
        peak = int(np.argmax(np.abs(np.asarray(control, dtype=float) - rest)))  # cyclic tests end at rest
        return f"{_fmt(forces[peak])} at {'grip stretch' if rest else 'shear'} {_fmt(control[peak], 4)}"

    def error(d):
        ref = d.get("reference") or {}
        errors = [v for k, v in ref.items() if k.startswith("max_relative_error") and v is not None]
        return _fmt(max(errors), 3) if errors else "—"

    def departure(key):
        return lambda d: _fmt((page.departures.get(d["input"].get("label", d["input"]["model"])) or {}).get(key), 4)

    elastic = [
        ("E measured [MPa]", per(lambda d: _measured_E(d) + _why(by_design_notes(d), "E"))),
        ("E input [MPa]", per(lambda d: _fmt(d["input"]["E"]))),
        ("ν measured", per(lambda d: _fmt(d["measured"]["nu"]) + _why(by_design_notes(d), "nu"))),
        ("ν input", per(lambda d: _fmt(d["input"]["nu"]))),
        ("E fit R²", per(lambda d: _fmt((d["measured"].get("E_fit") or {}).get("r2"), 8))),
    ] if kind.measures_E else []
    rows = [
        ("status", per(_model_status)),
        *elastic,
        *kind_rows(page.models),
        (f"force at max {kind.load_key} [N]", per(force)),
        *([("strain where |s − s_NH|/s_NH ≥ 5 %", per(departure("5%"))),
           ("strain where |s − s_NH|/s_NH ≥ 10 %", per(departure("10%")))]
          if kind.lateral_ratio and page.departures else []),  # nothing compared: no rows
        ("stress vs analytic, max rel. error", per(error)),
        ("Newton iterations (total)", per(lambda d: _newton_cost(d["solver"]))),
        ("linear solver; tangent kernel", per(lambda d: _solvers(d["solver"]))),
        ("cutbacks", per(lambda d: _fmt(sum(d["solver"]["cutbacks"])))),
        ("wall time [s]", per(lambda d: _fmt(d["timing"]["total_s"], 3))),
        ("DOFs", per(lambda d: _fmt(d["mesh"]["dofs"]))),
        ("mesh", per(lambda d: f"{d['mesh']['elements']} {d['mesh']['cell']} (order {d['mesh']['order']})"
                     + (f", {d['mesh']['symmetry']} model" if d["mesh"].get("symmetry", "none") != "none" else ""))),
        ("mesh quality", per(lambda d: _quality(d["mesh"].get("quality")))),
    ]
    if any(d.get("accuracy_estimate") for d in page.models):
        rows.append(("accuracy estimate (coarser companion solve)", per(_estimate)))
    rows += _per_model_cruciform_rows(page.models)
    for key, name in (("E", "E [MPa]"), ("nu", "ν")):  # effects.noise: intervals of the noisy instruments
        cells = [(d["measured"].get("uncertainty") or {}).get(key) for d in page.models]
        if any(cells):
            conf = next(c for c in cells if c)["confidence"]
            rows.append((f"{name} {100 * conf:g} % interval (noisy instruments)",
                         [f"[{_fmt(c['low'])}, {_fmt(c['high'])}]" if c else "—" for c in cells]))
    taylor = [page.checks.get(d["input"].get("label", d["input"]["model"]), {}).get("taylor") for d in page.models]
    if any(taylor):
        rows.append(("Taylor test order: energy / force (2 = consistent)",
                     [f"{t['energy_order']:.3f} / {t['force_order']:.3f}" if t else "—" for t in taylor]))
    return rows


def _estimate(d: dict) -> str:
    """E, ν and final-stress error estimates with their cost, or why there is none."""
    est = d.get("accuracy_estimate")
    if not est:
        return "—"
    if not est.get("available"):
        return f"not available: {html.escape(est.get('reason', ''))}"
    q = est["quantities"]
    parts = "; ".join(f"{name} ± {_fmt(q[key]['error'], 2)} ({_fmt(100 * q[key]['relative'], 2)} %)"
                      for key, name in (("E", "E"), ("nu", "ν"), ("final_stress", "final stress"))
                      if q.get(key) and q[key]["error"] is not None and q[key]["relative"] is not None)
    text = (f"{parts}; companion mesh.size {_fmt(est['companion_mesh_size'], 4)}, assumed order "
            f"{est['assumed_order']}, cost {_fmt(est['cost_s'], 3)} s")
    if est.get("exact_by_construction"):
        text += f". <b>Exact by construction</b>: {html.escape(est['note'])}"
    return text


def _per_model_cruciform_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """The cruciform rows (nominal vs centre stress, correction factor) with one value per model."""
    if not any(d.get("cruciform") for d in models):
        return []
    per_model = [dict(cruciform_rows(d.get("cruciform"))) for d in models]
    labels = list(dict.fromkeys(k for rows in per_model for k in rows))
    return [(label, [rows.get(label, "—") for rows in per_model]) for label in labels]


def _quality(quality) -> str:
    if not quality:
        return "—"
    if isinstance(quality, dict) and "min_quality" in quality:
        return (f"min {_fmt(quality['min_quality'], 3)}, mean {_fmt(quality.get('mean_quality'), 3)} "
                f"({html.escape(str(quality.get('measure', '')))}); "
                f"max aspect ratio {_fmt(quality.get('max_aspect_ratio'), 3)}")
    if isinstance(quality, dict):
        return ", ".join(f"{html.escape(str(k))} {_fmt(v, 3)}" for k, v in quality.items())
    return _fmt(quality)


def _image_source(folder: Path, name: str, inline: bool) -> str:
    if not inline:
        return html.escape(name)
    mime = mimetypes.guess_type(name)[0] or "application/octet-stream"
    return f"data:{mime};base64," + base64.b64encode((folder / name).read_bytes()).decode("ascii")


def _measured_E(d: dict) -> str:
    """E, or — with the reason it was not measured (e.g. the material yields before the window)."""
    m = d["measured"]
    if m["E"] is None and m.get("note"):
        return f"— <small>({html.escape(m['note'])})</small>"
    return _fmt(m["E"])


def _spring_note(page: ReportPage) -> str:
    for d in page.models:
        if d["input"]["model"] == "spring-network" and d["measured"]["nu"] is not None:
            check = page.checks.get("spring-network", {})
            return (f"<h2>Spring network: what its tessellation allows</h2><p>Measured ν = "
                    f"{_fmt(d['measured']['nu'], 4)} against the input ν = {_fmt(d['input']['nu'], 4)}; "
                    f"measured E = {_fmt(d['measured']['E'], 4)} MPa against the input "
                    f"{_fmt(d['input']['E'], 4)} MPa. The {_fmt(check.get('springs'))} springs have "
                    f"k̃ = {_fmt(check.get('stiffness_factor'))} E v<sub>s</sub>/L (v<sub>s</sub> the "
                    "spring's share of its elements' volume), the choice that gives E for a network whose "
                    "springs point in all directions equally, with ν = 1/4 whatever the input: central-force "
                    "networks obey Cauchy's relation λ = μ. On a real mesh both constants follow from the "
                    "tessellation, which the numbers above show.</p>")
    return ""


def _view3d(page: ReportPage, folder: Path, inline: bool) -> str:
    """The interactive view in a frame (single-file reports carry the page itself, in srcdoc)."""
    if not page.view3d:
        return ""
    src = html.escape(page.view3d)
    where = (f'srcdoc="{html.escape((folder / page.view3d).read_text(encoding="utf-8"))}"' if inline
             else f'src="{src}"')
    return (f'<h2>Interactive 3-D view</h2><iframe {where} title="interactive 3-D view" '
            'style="width:100%;height:640px;border:1px solid #ddd"></iframe><p><small>Drag to rotate, '
            'scroll to zoom; choose the model, the field and the load level; hover for values. '
            f'<a href="{src}">Open full page</a>.</small></p>')


def write_comparison(page: ReportPage, folder: Path, inline_images: bool = False) -> Path:
    """index.html in ``folder`` (which already holds the figures); inlined images when asked."""
    folder = Path(folder)
    heads = "".join(f"<th>{html.escape(d['input']['model'])}</th>" for d in page.models)
    rows = "".join(f"<tr><th>{html.escape(name)}</th>" + "".join(f"<td class=num>{v}</td>" for v in values)
                   + "</tr>" for name, values in comparison_rows(page))
    figures = "".join(
        f'<figure><img src="{_image_source(folder, f.file, inline_images)}" alt="{html.escape(f.file)}">'
        f"<figcaption>{f.caption}</figcaption></figure>" for f in page.figures)
    links = "".join(f"<li>{html.escape(model)}: " + ", ".join(f'<a href="{html.escape(x)}">{html.escape(x)}</a>'
                                                            for x in files) + "</li>"
                    for model, files in page.links.items())
    notes = "".join(f"<p>{n}</p>" for n in page.notes)
    prov = page.provenance
    out = folder / "index.html"
    out.write_text(f"""<!doctype html><html><head><meta charset="utf-8">
<title>vlab — {html.escape(page.title)}</title><style>{_STYLE}</style></head><body>
<h1>vlab report: {html.escape(page.title)}</h1>
<p>{html.escape(prov.get('description') or '')}</p>
<table><tr><th></th>{heads}</tr>{rows}</table>{notes}
{_view3d(page, folder, inline_images)}{figures}{_spring_note(page)}
<h2>Files</h2><ul>{links}</ul>
<h2>Provenance</h2>
<p>vlab {html.escape(prov['vlab_version'])} · {html.escape(prov['date'])} · scene content hash
<code>{html.escape(prov['scene_hash'])}</code>{html.escape(prov.get('override_note', ''))}</p>
<pre>{html.escape(prov['scene_text'])}</pre>
</body></html>""", encoding="utf-8")
    return out
