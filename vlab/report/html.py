"""A one-page HTML summary of a run (the full comparison report builds on the same pieces)."""

from __future__ import annotations

import html
import json
from pathlib import Path


def _fmt(value, digits: int = 5) -> str:
    if value is None:
        return "—"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return html.escape(str(value))


def summary_rows(data: dict) -> list[tuple[str, str]]:
    m, inp, solver, timing, mesh = (data["measured"], data["input"], data["solver"],
                                    data["timing"], data["mesh"])
    rows = [
        ("model", inp["model"]),
        ("E measured / input [MPa]", f"{_fmt(m['E'])} / {_fmt(inp['E'])}"),
        ("ν measured / input", f"{_fmt(m['nu'])} / {_fmt(inp['nu'])}"),
        ("force at last level [N]", _fmt(data["curve"]["force"][-1] if data["curve"]["force"] else None)),
        ("Newton iterations (total)", _fmt(sum(solver["newton_iterations"]))),
        ("cutbacks", _fmt(sum(solver["cutbacks"]))),
        ("mesh", f"{mesh['cell']} order {mesh['order']}, {mesh['elements']} elements, {mesh['dofs']} DOFs"),
        ("wall time [s]", _fmt(timing["total_s"], 3)),
    ]
    if m.get("E_fit"):
        rows.append(("E fit", f"{m['E_fit']['method']} over |strain| {m['E_fit']['window']}, "
                              f"{m['E_fit']['n_points']} points, R² = {m['E_fit']['r2']:.6f}"))
    stab = data.get("stability") or []
    if stab:
        unstable = [r for r in stab if not r["accepted"]]
        rows.append(("stability (inertia of K_ff)",
                     f"{len(stab) - len(unstable)} of {len(stab)} levels stable (no negative eigenvalue)"
                     + (f"; stopped at stretch {unstable[0]['stretch']}: "
                        f"{unstable[0]['negative_eigenvalues']} negative eigenvalue(s), "
                        f"limit point {unstable[0]['limit_point']}" if unstable else "")))
    ref = data.get("reference") or {}
    for k, v in ref.items():
        if k.startswith("max_relative_error"):
            rows.append((f"stress vs analytic ({k[-1]})", f"max relative error {_fmt(v, 3)}"))
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
