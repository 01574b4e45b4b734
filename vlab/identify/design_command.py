"""`vlab design FITFILE`: fit the file's data, then rank candidate tests by their Fisher information.

Writes DIR/design.json (``candidates``: combinations of candidate tests alone, best first;
``next``: each candidate test added to the fit file's data, best first, with the expected
reduction of every standard error; ``answer``: the best next test in words) and DIR/index.html.
Exit 0, 1 when the fit of the file's data did not converge (the design is then around a doubtful
card), 2 on invalid input (nothing written).
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

from rich.console import Console
from rich.text import Text

from vlab.fields import SceneError
from vlab.identify.design import CANDIDATE_KINDS, PlannedTest, combinations, data_rows, default_range, next_tests

__all__ = ["design_command", "parse_candidates", "parse_ranges"]


def parse_candidates(text: str | None) -> tuple[str, ...]:
    if text is None:
        return CANDIDATE_KINDS
    items = [t.strip() for t in text.split(",")]
    bad = [t for t in items if t not in CANDIDATE_KINDS]
    if not items or bad:
        raise SceneError(f"--candidates {text!r}: {', '.join(repr(b) for b in bad) or 'empty'} is not a homogeneous "
                         f"test kind vlab design can plan; allowed: a comma-separated subset of "
                         f"{','.join(CANDIDATE_KINDS)}")
    return tuple(dict.fromkeys(items))


def parse_ranges(text: str | None) -> dict[str, tuple[float, float]]:
    """"uniaxial=1.05:3,planar=1.05:2.5" → {kind: (lo, hi)}; stretches > 0, shear γ ≥ 0, lo < hi."""
    out = {}
    for item in ([] if text is None else [t.strip() for t in text.split(",")]):
        kind, _, span = item.partition("=")
        lo, _, hi = span.partition(":")
        try:
            lo_v, hi_v = float(lo), float(hi)
        except ValueError:
            lo_v = hi_v = float("nan")
        floor = 0.0 if kind.strip() == "simple-shear" else 1e-9
        if kind.strip() not in CANDIDATE_KINDS or not (floor <= lo_v < hi_v < 100):
            raise SceneError(f"--range {item!r}: expected KIND=LO:HI with KIND one of {', '.join(CANDIDATE_KINDS)} "
                             "and LO < HI (stretches > 0, simple-shear γ >= 0, below 100)")
        out[kind.strip()] = (lo_v, hi_v)
    return out


def _noise(outcome, noise: float | None, scale: float) -> float:
    """--noise, else the fit's residual scatter s; an s below 1e-9 of the residual's scale (1, or
    the largest |stress| for absolute residuals) is round-off of noise-free data, not a noise."""
    if noise is not None:
        if not (noise > 0):
            raise SceneError(f"--noise {noise!r}: must be > 0 (the residual scatter, relative or MPa)")
        return float(noise)
    s2 = outcome.data["information"]["residual_variance"]
    if not (s2 > (1e-9 * scale) ** 2):
        raise SceneError("the fit's residual scatter is zero or undefined (noise-free data, or no more points than "
                         "parameters): give --noise (the standard deviation of a measured stress, relative for "
                         "options.residual = \"relative\", MPa for \"absolute\")")
    return float(s2) ** 0.5


def _plans(kinds, ranges, fit_sets, points: int) -> list[PlannedTest]:
    return [PlannedTest(k, *(ranges.get(k) or default_range(k, fit_sets)), points) for k in kinds]


def parse_expect(text: str | None, model) -> np.ndarray | None:
    """"C10=0.3,C01=0.05" → the card values in ``model.names`` order (every constant, once)."""
    if text is None:
        return None
    names, got = list(model.names), {}
    for item in (t.strip() for t in text.split(",")):
        key, _, value = item.partition("=")
        try:
            v = float(value)
        except ValueError:
            v = float("nan")
        if key.strip() not in names or key.strip() in got or not np.isfinite(v):
            raise SceneError(f"--expect {item!r}: expected NAME=VALUE with NAME one of {', '.join(names)} "
                             "(each once) and a finite value")
        got[key.strip()] = v
    missing = [n for n in names if n not in got]
    if missing:
        raise SceneError(f"--expect: missing {', '.join(missing)} (give every constant of the model: "
                         f"{', '.join(names)})")
    return np.array([got[n] for n in names])


def design(spec, kinds, ranges, points: int, max_size: int, noise: float | None,
           expect: np.ndarray | None = None) -> dict:
    """design.json's dict for a validated homogeneous fit spec (around ``expect``, the expected
    card values, when given; else around the fitted card)."""
    from vlab.identify.fitting import fit_homogeneous

    outcome = fit_homogeneous(spec)
    scale = 1.0 if spec.residual == "relative" else max(float(np.max(np.abs(d.y))) for d in spec.datasets)
    s = _noise(outcome, noise, scale)
    model = spec.model
    x = outcome.x if expect is None else np.linalg.solve(model.transform, expect)
    fit_sets = [d for d in spec.datasets if d.role == "fit"]
    relative = spec.residual == "relative"
    plans = _plans(kinds, ranges, fit_sets, points)
    combos = combinations(model, x, plans, s, relative, max_size)
    J0 = data_rows(model, x, fit_sets, spec.residual)
    now, nxt = next_tests(model, x, J0, plans, s, relative)
    warnings = []
    if expect is None and outcome.data["identifiability"]["warning"]:
        warnings.append("the file's data do not identify the fitted card, so the design is around an arbitrary "
                        "point of its valley: give the expected constants with --expect")
    return {"name": spec.name, "model": outcome.data["model"], "warnings": warnings,
            "parameters": dict(zip(model.names, map(float, model.card_vector(x)))),
            "parameters_from": "--expect" if expect is not None else "fit",
            "fit_converged": outcome.converged, "noise": {"standard_deviation": s, "residual": spec.residual,
                                                          "source": "--noise" if noise is not None else "fit"},
            "points_per_test": points, "present_data": now, "answer": _answer(now, nxt),
            "next": nxt, "candidates": combos}


def _answer(now: dict, nxt: list[dict]) -> str:
    best = nxt[0]
    if best["verdict"] == "not determined":
        return f"no single candidate test determines every constant with the present data ({best['reason']})"
    parts = []
    for n, r in best["reduction"].items():
        if r is not None:
            parts.append(f"SE({n}) {-100 * r:+.3g} %")
    if best["now_determined"]:
        parts.append("determines " + ", ".join(best["now_determined"]))
    return f"add {best['label']} ({best['tests'][0]['points']} points): " + ", ".join(parts)


def _cell(v) -> str:
    return "—" if v is None else f"{v:.4g}" if isinstance(v, float) else html.escape(str(v))


def _rows(entries, names, extra: bool) -> str:
    out = []
    for e in entries:
        se = "".join(f"<td>{_cell(e['standard_errors'][n])}</td>" for n in names)
        red = "".join(f"<td>{_cell(None if e['reduction'][n] is None else -100 * e['reduction'][n])}</td>"
                      for n in names) if extra else ""
        out.append(f"<tr><td>{html.escape(e['label'])}</td>{se}{red}<td>{_cell(e['D'])}</td><td>{_cell(e['A'])}</td>"
                   f"<td>{html.escape(e['verdict'])}</td><td>{html.escape(e['reason'] or '')}</td></tr>")
    return "".join(out)


def page(d: dict) -> str:
    from vlab.report.html import _STYLE

    names = list(d["present_data"]["standard_errors"])
    se_h = "".join(f"<th>SE {html.escape(n)}</th>" for n in names)
    red_h = "".join(f"<th>Δ SE {html.escape(n)} (%)</th>" for n in names)
    tail = "<th>D</th><th>A</th><th>verdict</th><th>reason</th>"
    now = d["present_data"]
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>vlab design — {html.escape(d['name'])}</title>"
            f"<style>{_STYLE}</style></head><body><h1>{html.escape(d['name'])}: which test next</h1>"
            f"<p>{html.escape(d['answer'])}</p><p>Model {html.escape(d['model']['name'])}, residual scatter "
            f"{d['noise']['standard_deviation']:.4g} ({html.escape(d['noise']['residual'])}, from "
            f"{html.escape(d['noise']['source'])}). D = det(Cov_rel)^(1/2p), A = √(tr Cov_rel / p): relative "
            f"standard errors, smaller is better. Present data: {html.escape(now['verdict'])}"
            f"{' — ' + html.escape(now['reason']) if now['reason'] else ''}.</p>"
            f"<h2>Add one test to the present data</h2><table><tr><th>test</th>{se_h}{red_h}{tail}</tr>"
            f"{_rows(d['next'], names, True)}</table>"
            f"<h2>Candidate tests alone and combined</h2><table><tr><th>tests</th>{se_h}{tail}</tr>"
            f"{_rows(d['candidates'], names, False)}</table></body></html>")


def design_command(path: Path, out: Path | None, candidates: str | None, ranges: str | None, points: int,
                   max_size: int, noise: float | None, console: Console, force: bool = False,
                   expect: str | None = None, results: Console | None = None) -> int:
    """Errors and warnings on ``console`` (stderr in the CLI); the verdicts and the report's path on
    ``results`` (stdout; default ``console``)."""
    from vlab.identify.command import _destination
    from vlab.identify.fitfile import load_fit
    from vlab.report.folder import ReportFolderError, report_folder

    def invalid(label, exc) -> int:
        console.print(Text.assemble((label, "red"), f" {exc}"), highlight=False, soft_wrap=True)
        return 2

    try:
        spec = load_fit(path)
        if spec.fe is not None:
            raise SceneError("vlab design plans homogeneous tests; this fit file has a data set of kind = "
                             "\"specimen\" (FE in the loop), which it does not cover")
        kinds, spans = parse_candidates(candidates), parse_ranges(ranges)
        if not 3 <= points <= 10000:
            raise SceneError(f"--points {points}: must be 3..10000")
        if not 1 <= max_size <= len(kinds):
            raise SceneError(f"--combine {max_size}: must be 1..{len(kinds)} (the number of candidate kinds)")
        d = design(spec, kinds, spans, points, max_size, noise, parse_expect(expect, spec.model))
    except SceneError as exc:
        return invalid("invalid input", exc)
    try:
        dest = _destination(out or Path("reports") / f"{spec.name}-design", force, spec, path)
        with report_folder(dest, "design") as tmp:
            (tmp / "design.json").write_text(json.dumps(d, indent=2))
            (tmp / "index.html").write_text(page(d), encoding="utf-8")
    except ReportFolderError as exc:
        return invalid("invalid output folder", exc)
    results = results or console
    results.print(Text(f"{d['name']}: {d['model']['name']}, present data {d['present_data']['verdict']}"),
                  highlight=False)
    for w in d["warnings"]:
        console.print(Text.assemble("  ", ("warning", "yellow"), f" {w}"), highlight=False, soft_wrap=True)
    results.print(Text(f"  next: {d['answer']}"), highlight=False, soft_wrap=True)
    for e in d["candidates"][:5]:
        results.print(Text(f"  {e['label']}: {e['verdict']}, D {_cell(e['D'])}, A {_cell(e['A'])}"), highlight=False)
    results.print(Text(f"report: {dest.path / 'index.html'}"), highlight=False, soft_wrap=True)
    return 0 if d["fit_converged"] else 1
