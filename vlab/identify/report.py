"""The report folder of a fit: fit.json, curves.png, stability_map.png, card.toml, index.html.

Written through the project's one report-folder writer (vlab.report.folder: atomic, with a
manifest; it never replaces a folder vlab did not make unless forced).
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

from vlab.report.html import _STYLE
from vlab.report.folder import report_folder

__all__ = ["write_fit_report", "write_fit_files", "page"]


def _f(v, digits: int = 4) -> str:
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return html.escape(str(v))


def percent(v) -> str:
    """A share as a percentage; a number fit.json does not have (null: it was not finite) as —."""
    return "—" if v is None else f"{100 * v:.3g} %"


def _table(head, rows) -> str:
    th = "".join(f"<th>{html.escape(h)}</th>" for h in head)
    body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table><tr>{th}</tr>{body}</table>"


def unit_of(model: str, key: str) -> str:
    """A fitted constant's unit: the material registry's for the card's constants, MPa for the
    moduli a fit adds (μ of Neo-Hookean, K), "1" for dimensionless ones."""
    from vlab.materials.registry import MODELS

    entry = MODELS.get(model)
    units = {c.key: c.unit for c in ((entry.constants or ()) if entry is not None else ())}
    unit = units.get(key, "MPa" if key in ("mu", "K", "G") else "1")
    return "1" if unit == "-" else unit


def _parameter_rows(d: dict) -> list:
    rows, values = [], []
    for k, v in d["parameters"].items():
        values += [(f"{k}[{i}]", x) for i, x in enumerate(v)] if isinstance(v, list) else [(k, v)]
    for (name, value) in values:
        u = d["uncertainty"].get(name, {})
        unit = unit_of(d["model"]["name"], name.split("[")[0])
        if u.get("interval") is None:  # not determined: say why, never a number the fit does not have
            why = html.escape(u.get("reason") or "not determined")
            rows.append([html.escape(name), _f(value, 6), "not determined", why, unit])
            continue
        lo, hi = u["interval"]
        rows.append([html.escape(name), _f(value, 6), _f(u.get("standard_error")), f"{_f(lo)} … {_f(hi)}", unit])
    return rows


def _limit_text(side: dict | None, bound: str, lim: float) -> str:
    """'stable to 10', 'unstable from λ = …' or 'chains lock at λ = …' for one side of a kind."""
    if side is None:
        return "—"
    if side.get("locks_at") is not None:
        return f"stable up to the chains' locking at λ = {side['locks_at']:.5g}"
    if side["unstable_from"] is not None:
        return f"unstable {bound} λ = {side['unstable_from']:.5g}"
    return f"stable to {lim:g}"


def _stability_rows(st: dict) -> list:
    """A row per scanned path, then one per closed-form data set judged at its own states."""
    paths = [[kind, _limit_text(s["tension"], "from", 10), _limit_text(s["compression"], "below", 0.1),
              _f(s.get("stable_over_fitted_range"))] for kind, s in st["kinds"].items()]
    return paths + [[html.escape(name), f"{s['states']} states of the data", f"min eig D {_f(s['min_eigenvalue'], 4)} MPa",
                     _f(s["stable"])] for name, s in st.get("data_states", {}).items()]


def _fe_section(d: dict) -> str:
    """FE in the loop: solves and the homogeneous fit of the same readings."""
    fe = d.get("fe")
    if not fe:
        return ""
    if "field" in fe:  # FE model updating on DIC fields
        from vlab.identify.field_fit import field_section
        return field_section(d)
    hom = fe["homogeneous_fit"]
    head = f"<h2>FE in the loop</h2><p>{fe['solves']} whole-test solves of {html.escape(fe['scene'])}; "
    if not hom.get("parameters"):
        return head + f"{html.escape(hom.get('note', 'no closed-form comparison'))}.</p>"
    rows = [[html.escape(n), _f(d["parameters"][n], 6), _f(v, 6), f"{100 * hom['relative_difference'][n]:+.3g} %",
             _f(hom["difference_in_standard_errors"][n], 3)] for n, v in hom["parameters"].items()]
    return (head + f"the closed-form fit of the same readings (kind {html.escape(str(hom['kind']))}: an extension "
            "test's stress = force / A0 and stretch = 1 + strain; torsion by Rivlin's integrals; the thick sphere; "
            "the die's homogeneous state) for comparison: the error a specimen's inhomogeneity (and the mesh) "
            "would put into a closed-form fit.</p>"
            + _table(["constant", "FE fit", "closed-form fit", "difference", "difference (standard errors)"], rows)
            + (f"<p>{html.escape(hom['note'])}.</p>" if hom.get("note") else ""))


def _specimens_section(d: dict) -> str:
    """fit.json → specimens: each specimen's constants with their intervals, then the statistics
    between specimens per constant beside the pooled value (the card's)."""
    sp = d.get("specimens")
    if not sp:
        return ""
    if sp["statistics"] is None:
        return f"<h2>Specimens</h2><p>n = {sp['n']}: {html.escape(sp['reason'])}</p>"
    names = list(sp["statistics"])
    rows = []
    for s, r in sp["per_specimen"].items():
        cells = [html.escape(s), _f(r["converged"]), str(r["points"]),
                 "—" if r["rms_relative"] is None else f"{100 * r['rms_relative']:.3g} %"]
        for k in names:
            c = r["constants"].get(k)
            iv = c and c["interval"]
            cells.append("—" if c is None else f"{_f(c['value'], 5)}" + (f" ({_f(iv[0])} … {_f(iv[1])})" if iv else
                                                                         " (no interval)"))
        rows.append(cells)
    stats = [[html.escape(k), _f(st["mean"], 5), _f(st["standard_deviation"], 3),
              "—" if st["coefficient_of_variation"] is None else f"{100 * st['coefficient_of_variation']:.3g} %",
              str(st["n"]), f"{_f(st['min'], 5)} … {_f(st['max'], 5)}", _f(st["pooled"], 5),
              _f(st["pooled_within_range"]), html.escape(st["reason"] or "")] for k, st in sp["statistics"].items()]
    return (f"<h2>Specimens</h2><p>{sp['n']} specimens, each fitted on its own ({100 * d['confidence']:g} % "
            f"intervals); {html.escape(sp['note'])}.</p>"
            + _table(["specimen", "converged", "points", "rms relative"] + names, rows)
            + _table(["constant", "mean", "standard deviation", "cv", "n", "range", "pooled", "pooled in range",
                      "note"], stats))


def _cards(d: dict) -> str:
    """The solver cards of ``vlab fit --export`` (vlab.export), linked."""
    if not d.get("cards"):
        return ""
    links = "".join(f"<li><a href='{html.escape(f)}'>{html.escape(f)}</a></li>" for f in d["cards"])
    return f"<h2>Solver cards</h2><p>The card in each solver's own convention (vlab export):</p><ul>{links}</ul>"


def page(d: dict, images: list[tuple[str, str]]) -> str:
    """index.html of a fit dict and its figures [(file, caption)]."""
    corr = d["correlation"]
    ds_rows = [[html.escape(x["name"]), x["kind"], x["role"], str(x["points"]),
                percent(x['rms_relative']), percent(x['max_relative'])] for x in d["datasets"]]
    info = d["information"]
    starts = d["starts"]
    warn = "".join(f"<p class='warn'>⚠ {html.escape(w)}</p>" for w in d["warnings"])
    figs = "".join(f"<figure><img src='{f}' style='max-width:100%'><figcaption>{html.escape(c)}</figcaption>"
                   "</figure>" for f, c in images)
    status = "converged" if d["converged"] else f"NOT converged: {html.escape(str(d['reason']))}"
    if d["converged"] and not d.get("trust", {}).get("trustworthy", True):
        status += " but the card is not trustworthy: " + html.escape("; ".join(d["trust"]["because"]))
    return f"""<!doctype html><html><head><meta charset="utf-8">
<title>vlab fit — {html.escape(d['name'])}</title><style>{_STYLE} .warn{{color:#a40}}</style></head><body>
<h1>vlab fit — {html.escape(d['name'])}: {html.escape(d['model']['name'])}</h1>
<p>{status}; μ0 = {_f(d['model']['mu0'])} MPa; bulk: {html.escape(d['model']['bulk'])}.</p>{warn}
{figs}
<h2>Parameters ({100 * d['confidence']:g} % intervals)</h2>
{_table(['parameter', 'value', 'standard error', 'interval', 'unit'], _parameter_rows(d))}
<h2>Correlations</h2>
{_table([''] + corr['order'], [[html.escape(n)] + ["—" if v is None else f"{v:.3f}" for v in row] for n, row in zip(corr['order'], corr['matrix'])])}
<h2>Data sets</h2>
{_table(['data', 'kind', 'role', 'points', 'rms relative', 'max relative'], ds_rows)}
<h2>Fit</h2>
{_table(['n', 'p', 'AIC', 'BIC', 'residual variance', 'starts at best', 'objective spread of others'],
        [[str(info['points']), str(info['parameters']), _f(info['AIC']), _f(info['BIC']), _f(info['residual_variance']),
          f"{starts['reached_best']} of {starts['count']}",
          '—' if not starts['others_objective_ratio'] else f"{starts['others_objective_ratio']['min']:.3g} … "
          f"{starts['others_objective_ratio']['max']:.3g} × best"]])}
<h2>Drucker stability</h2>
{_table(['kind', 'tension', 'compression', 'stable over the fitted range'], _stability_rows(d['stability']))}
{_fe_section(d)}
{_specimens_section(d)}
<h2>Card</h2><pre>{html.escape(d['card']['toml'])}</pre><p>{html.escape(d['card']['note'])}</p>{_cards(d)}
<p>Timing: fit {d['timing']['fit_s']:.3g} s, total {d['timing']['total_s']:.3g} s.</p>
</body></html>"""


def strict(o):
    """o with every non-finite float (NaN, ±inf) replaced by None, so that the JSON is strict
    (a parser that refuses NaN and Infinity reads it); a missing number is null and the record
    beside it says why."""
    if isinstance(o, dict):
        return {k: strict(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [strict(v) for v in o]
    if isinstance(o, np.ndarray):
        return strict(o.tolist())
    if isinstance(o, (np.floating, np.integer)):
        o = o.item()
    if isinstance(o, float) and not np.isfinite(o):
        return None
    return o


def json_text(d) -> str:
    """Strict JSON text of d (indent 2): no NaN or Infinity tokens."""
    return json.dumps(strict(d), indent=2, default=_json_default, allow_nan=False)


def _json_default(o):
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    raise TypeError(type(o))


def write_fit_report(outcome, out, fit_text: str | None = None) -> dict:
    """Write the folder (out: a path or a checked vlab.report.folder.Destination); returns fit.json's dict."""
    with report_folder(out, "fit") as tmp:
        return write_fit_files(outcome, tmp, fit_text)


def write_fit_files(outcome, tmp: Path, fit_text: str | None = None) -> dict:
    """fit.json, card.toml, the figures and index.html into an existing folder."""
    from vlab.identify.fitting import curves
    from vlab.identify.plots import plot_curves, plot_stability_map

    d = outcome.data = strict(outcome.data)  # what the console and the page show is what fit.json holds
    sets = [s for s in outcome.spec.datasets if s.kind not in ("specimen", "field")]
    tmp = Path(tmp)
    images = list(outcome.extras.get("figures", []))
    if sets:
        plot_curves(outcome, [curves(outcome, s) for s in sets], tmp / "curves.png")
        images.append(("curves.png", "Data (points; orange: held out, predicted only) against the fitted "
                       "model with its delta-method confidence band; below: relative residuals."))
    from vlab.identify.records.plots import cleanup_figures
    images += cleanup_figures(outcome.spec.datasets, tmp)  # raw machine exports against the cleaned curves
    plot_stability_map(outcome, tmp / "stability_map.png")
    images.append(("stability_map.png", "Drucker stability of the fitted card over the (λ1, λ2) plane; the "
                   "paths of the uniaxial, equibiaxial and planar tests, dashed where unstable."))
    for name, writer in outcome.extras.get("writers", []):
        writer(tmp / name)
    d["files"] = ["fit.json", "index.html", "card.toml"] + [f for f, _ in images] + d.get("cards", [])
    (tmp / "fit.json").write_text(json_text(d))
    (tmp / "card.toml").write_text(d["card"]["toml"])
    if fit_text is not None:
        (tmp / "fit.toml").write_text(fit_text)
    (tmp / "index.html").write_text(page(d, images), encoding="utf-8")
    return d
