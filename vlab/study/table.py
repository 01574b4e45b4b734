"""Summaries -> flat table rows -> CSV and a standalone HTML page (the sweep report)."""

from __future__ import annotations

import csv
import html
import json
from pathlib import Path

from vlab.report.folder import destination, report_folder

STYLE = """body{font-family:sans-serif;max-width:90rem;margin:2rem auto;padding:0 1rem;color:#222}
table{border-collapse:collapse;margin:1rem 0;font-size:.9rem}th,td{border:1px solid #ccc;padding:.25rem .5rem}
td.num{text-align:right;font-variant-numeric:tabular-nums}.ok{color:#060}.fail{color:#a00}
tr.pareto td{background:#eef7ee}img{max-width:100%}small{color:#666}"""

COLUMNS = (  # (header, path into the summary)
    ("status", ("status",)),
    ("E [MPa]", ("measured", "E")),
    ("nu", ("measured", "nu")),
    ("final force [N]", ("measured", "final_force")),
    ("final stress [MPa]", ("measured", "final_stress")),
    ("DOFs", ("mesh", "dofs")),
    ("Newton iterations", ("solver", "newton_iterations")),
    ("wall [s]", ("timing", "wall_s")),
    ("mesh [s]", ("timing", "mesh_s")),
    ("assembly [s]", ("timing", "assembly_s")),
    ("linear solves [s]", ("timing", "linear_solve_s")),
    ("other solver [s]", ("timing", "solve_other_s")),
    ("measure [s]", ("timing", "measure_s")),
    ("report [s]", ("timing", "report_s")),
    ("compile [s]", ("timing", "compile_s")),  # before the clock, not in wall (vlab.study.warm)
    ("peak RSS [MB]", ("memory", "peak_rss_mb")),
    ("cached", ("cache_hit",)),
    ("diagnosis", ("diagnosis",)),
)


def _get(summary: dict, path: tuple[str, ...]):
    value = summary
    for key in path:
        if not isinstance(value, dict):
            return None
        value = value.get(key)
    return value


def table_rows(summaries: list[dict], extra: tuple = ()) -> tuple[list[str], list[list]]:
    """Headers and rows: the grid keys first (from the labels), then ``extra`` and COLUMNS."""
    keys = list(dict.fromkeys(k for s in summaries for k in (s.get("label") or {})))
    columns = tuple(extra) + COLUMNS
    headers = keys + [h for h, _ in columns]
    rows = [[(s.get("label") or {}).get(k) for k in keys] + [_get(s, p) for _, p in columns]
            for s in summaries]
    return headers, rows


def write_csv(headers: list[str], rows: list[list], path: Path) -> None:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(headers)
        writer.writerows(["" if v is None else v for v in row] for row in rows)


def _cell(value) -> str:
    if value is None:
        return "<td>—</td>"
    if isinstance(value, bool):
        return f"<td>{'yes' if value else 'no'}</td>"
    if isinstance(value, float):
        return f"<td class=num>{value:.5g}</td>"
    if isinstance(value, int):
        return f"<td class=num>{value}</td>"
    text = html.escape(str(value))
    cls = {"ok": "ok", "failed": "fail", "invalid": "fail", "error": "fail"}.get(str(value))
    return f"<td class={cls}>{text}</td>" if cls else f"<td>{text}</td>"


def html_table(headers: list[str], rows: list[list], highlight: set[int] = frozenset()) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
    body = "".join(f"<tr{' class=pareto' if i in highlight else ''}>{''.join(_cell(v) for v in row)}</tr>"
                   for i, row in enumerate(rows))
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def page(title: str, body: str) -> str:
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
            f"<style>{STYLE}</style></head><body><h1>{html.escape(title)}</h1>{body}</body></html>")


def _chart(summaries: list[dict], tmp: Path) -> str:
    """The chart's figure element (vlab.study.sweep_plots), or a line saying why there is none."""
    from vlab.study.sweep_plots import plot_sweep, swept_keys

    panels = plot_sweep(summaries, tmp / "sweep.png")
    if panels is None:
        return "<p><small>No chart: no run completed.</small></p>" if swept_keys(summaries) else ""
    keys = swept_keys(summaries)
    lines = f"; a line per value of {html.escape(', '.join(keys[1:]))}" if len(keys) > 1 else ""
    return (f"<figure><img src='sweep.png' alt='{html.escape(keys[0])} against each measured quantity'>"
            f"<figcaption>{html.escape(keys[0])} against each quantity the runs measured, one panel each{lines}; "
            "failed or invalid runs have no point (their diagnosis is in the table).</figcaption></figure>")


def write_sweep_report(folder: Path, title: str, summaries: list[dict], meta: dict) -> Path:
    """``folder``/sweep.csv, sweep.json (every summary + meta) and index.html, written atomically."""
    from vlab.study.commands import sweep_record

    headers, rows = table_rows(summaries)
    failed = sum(s["status"] != "ok" for s in summaries)
    intro = (f"<p>{len(summaries)} runs: {len(summaries) - failed} completed, {failed} failed or invalid "
             f"(diagnosis in the last column); {meta.get('cache_hits', 0)} taken from the cache, "
             f"{meta.get('computed', 0)} computed.</p>")
    timing = meta.get("seconds") or {}
    if timing:
        intro += (f"<p><small>Dask: cluster start {timing['cluster_start_s']:.2f} s, compute "
                  f"{timing['compute_s']:.2f} s on {timing['threads']} worker thread(s), overhead "
                  f"≈ {timing['overhead_per_run_s']:.2f} s per run (elapsed × threads − Σ run wall) / runs."
                  f"</small></p>")
    with report_folder(folder, "sweep") as tmp:
        write_csv(headers, rows, tmp / "sweep.csv")
        (tmp / "sweep.json").write_text(json.dumps(sweep_record(meta, summaries), indent=1, default=str))
        chart = _chart(summaries, tmp)
        (tmp / "index.html").write_text(page(title, intro + chart + html_table(headers, rows)), encoding="utf-8")
    return destination(folder).path / "index.html"
