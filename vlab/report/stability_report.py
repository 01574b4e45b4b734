"""The stability suite's report: results.json (every case with its figures) and index.html (the
table, the buckling study against Euler, the mode renders). Consumes results, computes no physics."""

from __future__ import annotations

import datetime as _dt
import html
import json
from pathlib import Path

from vlab.report.results import _clean
from vlab.report.writer import atomic_folder
from vlab import __version__

STYLE = """body{font-family:sans-serif;margin:1.5em;max-width:1250px}table{border-collapse:collapse;
margin:1em 0}td,th{border:1px solid #bbb;padding:4px 8px;font-size:13px;vertical-align:top}
th{background:#eee}.pass{background:#d9f2d9}.fail{background:#f8d0d0}td.num{text-align:right}
figure{display:inline-block;margin:0.5em}img{max-width:600px;border:1px solid #ccc}"""


def suite_dict(results, mode: str, total_seconds: float) -> dict:
    return _clean({
        "vlab_version": __version__,
        "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "mode": mode, "total_seconds": total_seconds,
        "passed": sum(r.passed for r in results), "failed": sum(not r.passed for r in results),
        "cases": [r.as_dict() for r in results],
    })


def write_stability_report(results, out: Path, mode: str, total_seconds: float, figures_dir: Path) -> dict:
    """Write results.json, index.html and the case figures (from ``figures_dir``) into ``out``."""
    data = suite_dict(results, mode, total_seconds)
    with atomic_folder(out) as tmp:
        for case in data["cases"]:
            for name in case["figures"]:
                (tmp / name).write_bytes((figures_dir / name).read_bytes())
        (tmp / "results.json").write_text(json.dumps(data, indent=1), encoding="utf-8")
        (tmp / "index.html").write_text(_page(data), encoding="utf-8")
    return data


def _cell(value, css: str = "") -> str:
    return f"<td class='{css}'>{html.escape(str(value))}</td>"


def _page(data: dict) -> str:
    rows = []
    for c in data["cases"]:
        neg = "–" if c["negative_eigenvalues"] is None else c["negative_eigenvalues"]
        rows.append("<tr>" + _cell(c["name"]) + _cell(c["expected"]) + _cell(c["got"])
                    + _cell("yes" if c["converged"] else "no") + _cell(c["iterations"], "num")
                    + _cell(c["cutbacks"], "num") + _cell(neg, "num") + _cell(f"{c['seconds']:.2f} s", "num")
                    + _cell("pass" if c["passed"] else "FAIL", "pass" if c["passed"] else "fail") + "</tr>")
    head = "".join(f"<th>{h}</th>" for h in ("case", "expected", "got", "converged", "Newton iterations",
                                              "cutbacks", "negative eigenvalues", "time", "result"))
    figures = "".join(f"<figure><img src='{html.escape(f)}' alt='{html.escape(f)}'><figcaption>"
                      f"{html.escape(c['name'])}</figcaption></figure>"
                      for c in data["cases"] for f in c["figures"])
    return f"""<!doctype html><html><head><meta charset="utf-8"><title>vlab stability suite</title>
<style>{STYLE}</style></head><body>
<h1>vlab stability suite</h1>
<p>{data['passed']} passed, {data['failed']} failed ({html.escape(data['mode'])} run, {data['total_seconds']:.1f} s
wall clock, vlab {html.escape(data['vlab_version'])}, {html.escape(data['date'])}).
Each hard case must converge to the right answer or stop with a diagnosis a user can act on.</p>
<table><tr>{head}</tr>{''.join(rows)}</table>
{_buckling_table(data)}
{'<h2>Critical modes</h2>' + figures if figures else ''}
</body></html>"""


def _buckling_table(data: dict) -> str:
    strips = [c for c in data["cases"] if c["details"].get("slenderness")]
    if not strips:
        return ""
    rows = []
    for c in sorted(strips, key=lambda c: c["details"]["slenderness"]):
        d, e = c["details"], c["details"]["euler"]
        lo, hi = d["strain_bracket"]
        rows.append("<tr>" + _cell(f"{d['slenderness']:g}") + _cell(f"{lo:.5f} … {hi:.5f}", "num")
                    + _cell(f"{e['euler_strain']:.5f}", "num") + _cell(f"{e['critical_strain']:.5f}", "num")
                    + _cell(f"{100 * d['relative_difference']:+.2f} %", "num")
                    + _cell(f"{e['current_geometry_strain']:.5f}", "num")
                    + _cell(f"{100 * d['relative_difference_current_geometry']:+.2f} %", "num")
                    + _cell(d["dofs"], "num") + "</tr>")
    head = "".join(f"<th>{h}</th>" for h in (
        "L/t", "FE critical grip strain (bracket)", "Euler P_E/(EA)", "with shear correction P_cr/(EA)",
        "FE vs P_cr", "P_cr on the pre-buckling geometry", "FE vs that", "DOFs"))
    return f"""<h2>Clamped strip buckling against Euler</h2>
<p>Neo-Hookean strip (E = 10 MPa, ν = 0.3), thickness t = 1 mm, width 2 mm, clamped grips, Q2 hexahedra
of t/2. P_E = 4π²EI/L², P_cr = P_E/(1 + P_E/(κGA)), κ = 5/6. The finite-element strain is the grip strain
between the last stable and the first unstable state. The FE lies above the beam formula for stubby strips
because beam theory ignores the pre-buckling change of geometry (the strip is shorter and thicker at ε_cr;
with that geometry the formula is within 1 %) and the clamps that also stop the end sections' Poisson
expansion (a 3D end effect); both vanish as L/t grows.</p>
<table><tr>{head}</tr>{''.join(rows)}</table>"""
