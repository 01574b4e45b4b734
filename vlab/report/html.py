"""The HTML pages of a run and of a comparison (their rows: vlab/report/table_rows.py)."""

from __future__ import annotations

import html
import json
from pathlib import Path

from vlab.report.table_rows import _fmt, comparison_rows, cruciform_rows, summary_rows  # noqa: F401 (re-exported)


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
    sections: list[str] = field(default_factory=list)  # whole HTML sections after the figures (DIC)


def _image_source(folder: Path, name: str, inline: bool) -> str:
    if not inline:
        return html.escape(name)
    mime = mimetypes.guess_type(name)[0] or "application/octet-stream"
    return f"data:{mime};base64," + base64.b64encode((folder / name).read_bytes()).decode("ascii")


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
{_view3d(page, folder, inline_images)}{figures}{"".join(page.sections)}{_spring_note(page)}
<h2>Files</h2><ul>{links}</ul>
<h2>Provenance</h2>
<p>vlab {html.escape(prov['vlab_version'])} · {html.escape(prov['date'])} · scene content hash
<code>{html.escape(prov['scene_hash'])}</code>{html.escape(prov.get('override_note', ''))}</p>
<pre>{html.escape(prov['scene_text'])}</pre>
</body></html>""", encoding="utf-8")
    return out
