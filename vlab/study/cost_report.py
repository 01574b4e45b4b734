"""The cost study's report: error against time (log–log, one curve per knob, Pareto front), the
table behind it, the reference used and a plain-language recommendation."""

from __future__ import annotations

import html
import json
from pathlib import Path

from vlab.report import figures as plt  # pyplot-free Agg figures

from vlab.report.folder import destination, report_folder  # noqa: E402
from vlab.study.cost import CostAnalysis, run_seconds  # noqa: E402
from vlab.study.commands import ERROR_COLUMNS, cost_record, cost_table  # noqa: E402,F401  (ERROR_COLUMNS: public here too)
from vlab.study.table import html_table, page, write_csv  # noqa: E402

ERROR_FLOOR = 1e-17  # log axes: errors at exactly zero are drawn at this floor


def plot_error_time(summaries: list[dict], analysis: CostAnalysis, target: float, path: Path) -> None:
    fig, ax = plt.subplots(figsize=(8.0, 5.2), dpi=120)
    knobs = list(dict.fromkeys(s["label"]["knob"] for s in summaries))
    for knob in knobs:
        pts = sorted((run_seconds(s), max(e["max"], ERROR_FLOOR))
                     for s, e in zip(summaries, analysis.errors)
                     if s["label"]["knob"] == knob and e and e["max"] is not None)
        if pts:
            ax.plot(*zip(*pts), "o-", ms=4, lw=1.2, label=knob)
    front = sorted((run_seconds(summaries[i]), max(analysis.errors[i]["max"], ERROR_FLOOR)) for i in analysis.front)
    if front:
        ax.step(*zip(*front), where="post", color="k", lw=1.0, alpha=0.6)
        ax.plot(*zip(*front), "o", ms=10, mfc="none", mec="k", label="Pareto front")
    ax.axhline(target, color="tab:red", ls="--", lw=1, label=f"target {target:.3g}")
    if analysis.best is not None:
        s = summaries[analysis.best]
        ax.plot([run_seconds(s)], [max(analysis.errors[analysis.best]["max"], ERROR_FLOOR)], "*",
                ms=16, color="gold", mec="k", label="recommended", zorder=5)
    if analysis.round_off:
        ax.text(0.02, 0.95, "every mesh at round-off: no convergence trend", transform=ax.transAxes,
                fontsize=9, color="tab:red", va="top")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("compute time per run [s] (mesh + solve + measure)")
    ax.set_ylabel("largest relative error of E, ν, final force, final stress")
    ax.set_title(f"Error against time — reference: {analysis.reference_kind}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7.5, loc="best")
    plt.save(fig, path)


def write_cost_report(folder: Path, title: str, summaries: list[dict], analysis: CostAnalysis,
                      target: float, meta: dict) -> Path:
    headers, rows = cost_table(summaries, analysis)
    reference = "".join(
        f"<tr><th>{html.escape(q)}</th><td class=num>{_num(analysis.reference.get(q))}</td>"
        f"<td>{_num(analysis.orders.get(q), 3)}</td><td>{html.escape(analysis.notes.get(q, ''))}</td></tr>"
        for q in analysis.reference)
    kind = ("the analytic homogeneous solution of the scene's model (the test kind's reference, vlab.loading.kinds)"
            if analysis.reference_kind == "analytic" else
            "per quantity, the Richardson extrapolation of the mesh family (order, cell) closest to its own "
            "limit, each family fitted on the effective element size h_eff = (volume / elements)^(1/3) "
            "of its three finest meshes")
    fixed = meta.get("fixed_mesh")  # an imported mesh: why there is no mesh-size family
    body = ((f"<p><b>No mesh study.</b> {html.escape(fixed)}</p>" if fixed else "")
            + f"<p><b>Recommendation.</b> {html.escape(analysis.recommendation)}</p>"
            f"<p>Reference: {kind}. Errors are relative, |q − q_ref| / |q_ref|.</p>"
            f"<table><tr><th>quantity</th><th>reference</th><th>observed order</th><th>note</th></tr>"
            f"{reference}</table>{_fits_table(analysis)}"
            f"<figure><img src='error_time.png' alt='error against time'><figcaption>Largest relative "
            f"error against compute time (mesh + solve + measure), one curve per knob; circled: the Pareto front (no run is both "
            f"faster and more accurate); dashed: the target.</figcaption></figure>"
            f"<p><small>Time split per run: mesh, assembly, linear solves (factorization + solve), other "
            f"solver work, measurement, report (plots + HTML{'' if meta.get('render') else '; 3D renders off'}). "
            f"Peak RSS: {html.escape(str(meta.get('memory_method', '')))}. Pareto rows are shaded. "
            f"Timings were measured on a shared machine; cached runs keep the time they first took."
            f"</small></p>" + html_table(headers, rows, set(analysis.front)))
    with report_folder(folder, "cost") as tmp:
        plot_error_time(summaries, analysis, target, tmp / "error_time.png")
        write_csv(headers, rows, tmp / "cost.csv")
        (tmp / "cost.json").write_text(json.dumps(cost_record(meta, analysis, summaries), indent=1, default=str))
        (tmp / "index.html").write_text(page(title, body), encoding="utf-8")
    return destination(folder).path / "index.html"


def _fits_table(analysis: CostAnalysis) -> str:
    """Every family's extrapolation per quantity: the effective sizes, the observed order, q*."""
    rows = "".join(
        f"<tr><td>{html.escape(q)}</td><td>{html.escape(fit['family'])}</td>"
        f"<td>{', '.join(f'{h:.3g}' for h in fit['h_eff'])}</td><td>{_num(fit['order'], 3)}</td>"
        f"<td class=num>{_num(fit['value'])}</td><td>{_num(fit['correction'], 2)}</td>"
        f"<td>{'' if fit['valid'] else html.escape(fit['reason'])}</td></tr>"
        for q, fits in analysis.fits.items() for fit in fits)
    if not rows:
        return ""
    return ("<p>Richardson per mesh family (finest three levels, h_eff in mm, finest first; correction = "
            "|q* − q_finest| / |q*|):</p><table><tr><th>quantity</th><th>family</th><th>h_eff</th>"
            f"<th>observed order</th><th>q*</th><th>correction</th><th>not valid because</th></tr>{rows}</table>")


def _num(x, digits: int = 8) -> str:
    return "—" if x is None else f"{x:.{digits}g}"
