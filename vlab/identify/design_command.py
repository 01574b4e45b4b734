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
import time
from pathlib import Path

import numpy as np

from rich.console import Console
from rich.text import Text

from vlab.fields import SceneError
from vlab.identify.design import CANDIDATE_KINDS, PlannedTest, combinations, data_rows, default_range, next_tests

__all__ = ["design_command", "parse_candidates", "parse_ranges"]

COMBINE = 3  # --combine's default: combinations of up to three tests (fewer if there are fewer candidates)


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


def _points_ok(points: int) -> bool:
    """--points: 3..10000 (SceneError otherwise)."""
    if not 3 <= points <= 10000:
        raise SceneError(f"--points {points}: must be 3..10000")
    return True


def parse_ranges(text: str | None) -> dict[str, tuple[float, float]]:
    """"uniaxial=1.05:3,planar=1.05:2.5" → {kind: (lo, hi)}; stretches > 0, shear γ ≥ 0, lo < hi;
    "specimen=0.05:0.5": a specimen test's extensometer strain range (> −1)."""
    out = {}
    for item in ([] if text is None else [t.strip() for t in text.split(",")]):
        kind, _, span = item.partition("=")
        lo, _, hi = span.partition(":")
        try:
            lo_v, hi_v = float(lo), float(hi)
        except ValueError:
            lo_v = hi_v = float("nan")
        floor = {"simple-shear": 0.0, "specimen": -1.0 + 1e-9}.get(kind.strip(), 1e-9)
        if kind.strip() not in CANDIDATE_KINDS + ("specimen",) or not (floor <= lo_v < hi_v < 100):
            raise SceneError(f"--range {item!r}: expected KIND=LO:HI with KIND one of {', '.join(CANDIDATE_KINDS)} "
                             "or specimen and LO < HI (stretches > 0, simple-shear γ >= 0, specimen extensometer "
                             "strain > -1, below 100)")
        out[kind.strip()] = (lo_v, hi_v)
    return out


def _elongation_sd(value: float | None) -> float:
    if value is None:
        return 0.0
    if not (np.isfinite(value) and value >= 0):
        raise SceneError(f"--extensometer-std {value!r}: must be >= 0 (mm of elongation, standard deviation)")
    return float(value)


def parse_list(text: str | None, option: str, kind: str) -> list:
    """"a.toml,b.toml" → [Path, ...] (kind "path"); "10,20" → [float > 0, ...] (kind "mm")."""
    if text is None:
        return []
    items = [t.strip() for t in text.split(",")]
    if kind == "path":
        missing = [t for t in items if not t or not Path(t).is_file()]
        if missing:
            raise SceneError(f"{option} {text!r}: {', '.join(repr(m) for m in missing)} is not a scene file")
        return [Path(t) for t in items]
    try:
        values = [float(t) for t in items]
    except ValueError:
        values = [float("nan")]
    if not all(np.isfinite(v) and v > 0 for v in values):
        raise SceneError(f"{option} {text!r}: expected comma-separated gauge lengths in mm, each > 0")
    return values


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


def parse_expect(text: str | None, names) -> np.ndarray | None:
    """"C10=0.3,C01=0.05" → the values of ``names`` in their order (every constant, once)."""
    if text is None:
        return None
    names, got = list(names), {}
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
        warnings.append(VALLEY)
    return {"name": spec.name, "model": outcome.data["model"], "warnings": warnings,
            "parameters": dict(zip(model.names, map(float, model.card_vector(x)))),
            "parameters_from": "--expect" if expect is not None else "fit",
            "fit_converged": outcome.converged, "noise": {"standard_deviation": s, "residual": spec.residual,
                                                          "source": "--noise" if noise is not None else "fit"},
            "points_per_test": points, "present_data": now, "answer": _answer(now, nxt),
            "next": nxt, "candidates": combos}


VALLEY = ("the file's data do not identify the fitted card, so the design is around an arbitrary point of its "
          "valley: give the expected constants with --expect")


def _designable(spec) -> dict:
    """spec.fe, if its scene is one vlab design plans (vlab.identify.fe_design.check_designable);
    SceneError for DIC fields (kind = "field": no test design yet)."""
    from vlab.identify.fe_design import check_designable

    if any(d.kind == "field" for d in spec.datasets):
        raise SceneError("vlab design plans homogeneous and specimen (kind = \"specimen\") tests; a fit file of DIC "
                         "fields (kind = \"field\") has no test design yet")
    check_designable(spec.fe["scene"], "fe.scene")
    return spec.fe


def design_fe(spec, kinds, ranges, points: int, max_size: int | None, noise: float | None, expect: np.ndarray | None,
              specimens, gauges, elongation_sd: float = 0.0) -> dict:
    """design.json's dict for a fit file with specimen data (FE in the loop): candidate specimen tests
    (the fit's scene and ``specimens``, each at its own and at ``gauges`` gauge lengths, over the
    extensometer strain range, extensometer elongation scatter ``elongation_sd`` mm) and, with
    ``kinds``, homogeneous tests of the scene's law (relative residuals only: a force scatter in N is
    no stress scatter), around the fitted (or expected) constants; fitted first unless both
    --expect and --noise are given."""
    from vlab.identify.design import add_each, combine, range_options
    from vlab.identify.fe_design import data_rows, specimen_candidates, specimen_rows, specimen_runs, strain_range
    from vlab.identify.fe_loop import fit_specimen

    fe, names, relative = _designable(spec), list(spec.fe["parameters"]), spec.residual == "relative"
    if kinds and not relative:
        raise SceneError("--candidates with a specimen fit file needs options.residual = \"relative\" (its force "
                         "scatter in N has no stress equivalent for homogeneous tests); give --specimens instead")
    max_size = _combine_size(max_size, (1 + len(specimens)) * (1 + len(gauges)) + len(kinds),
                             "the number of candidate tests: scenes × gauge lengths, plus the homogeneous kinds")
    t0 = time.perf_counter()
    candidates = specimen_candidates(fe, specimens, gauges)  # bad scenes and gauge lengths before any solve
    outcome = fit_specimen(spec) if expect is None or noise is None else None
    p = expect if expect is not None else np.array([outcome.data["parameters"][n] for n in names])
    values = fe["fixed"] | dict(zip(names, map(float, p)))
    s = _noise(outcome, noise, 1.0 if relative else max(float(np.max(np.abs(d.y))) for d in spec.datasets))
    lo, hi = ranges.get("specimen") or strain_range(spec)
    runs = specimen_runs(candidates, values, lo, hi, points)
    tests = [(r.test, specimen_rows(r.sim, r.test, relative, s, elongation_sd)) for r in runs]
    options = [(q, specimen_rows(r.sim, q, relative, s, elongation_sd)) for r in runs for q in range_options(r.test)]
    if kinds:
        more_tests, more_options = _homogeneous_of_scene(fe, kinds, ranges, values, names, (lo, hi), points, relative)
        tests, options = tests + more_tests, options + more_options
    combos = combine(tests, s, p, names, max_size)
    # runs[0] is fe.scene at its own gauge length: the run the present readings come from
    now, nxt = add_each(data_rows(spec, runs[0], s, elongation_sd), options, s, p, names)
    valley = outcome is not None and expect is None and not outcome.data["identifiability"]["identifiable"]
    return _fe_record(spec, names, p, expect, outcome, noise, s, points, now, nxt, combos, [VALLEY] * valley,
                      {"scene": fe["scene_path"], "parameters": names,
                       "held": {k: v for k, v in fe["fixed"].items() if k not in names},
                       "strain_range": [lo, hi], "extensometer_std_mm": elongation_sd,
                       "runs": [r.describe() for r in runs], "seconds": time.perf_counter() - t0})


def _homogeneous_of_scene(fe, kinds, ranges, values: dict, names: list, strains, points: int, relative: bool):
    """The rows of homogeneous candidate tests of the specimen scene's closed-form law at ``values``
    (the constants the fit holds fixed drop out), with their range options: (tests, options)."""
    from vlab.identify.datasets import Dataset
    from vlab.identify.design import plan_rows, range_options
    from vlab.identify.fe_loop import closed_form

    model = closed_form(fe, "fit")
    x = np.linalg.solve(model.transform, [values[n] for n in model.names])
    cols = [list(model.names).index(n) for n in names]
    as_uniaxial = [Dataset("specimen", "", "uniaxial", "fit", 1.0, "nominal", 1.0 + np.array(strains), None,
                           np.zeros(2))]
    plans = _plans(kinds, ranges, as_uniaxial, points)
    tests = [(q, plan_rows(model, x, q, relative)[:, cols]) for q in plans]
    options = [(q, plan_rows(model, x, q, relative)[:, cols]) for pl in plans for q in range_options(pl)]
    return tests, options


def _fe_record(spec, names, p, expect, outcome, noise, s, points, now, nxt, combos, warnings, fe_block) -> dict:
    """design.json's dict of an FE-in-the-loop design (design_fe's docstring)."""
    return {"name": spec.name, "model": {"name": spec.fe["model"], "fe": True}, "warnings": warnings,
            "parameters": dict(zip(names, map(float, p))),
            "parameters_from": "--expect" if expect is not None else "fit",
            "fit_converged": None if outcome is None else outcome.converged,
            "noise": {"standard_deviation": s, "residual": spec.residual,
                      "source": "--noise" if noise is not None else "fit", "of": "load-cell force"},
            "points_per_test": points, "present_data": now, "answer": _answer(now, nxt),
            "next": nxt, "candidates": combos, "fe": fe_block}


def _combine_size(max_size: int | None, count: int, what: str) -> int:
    """--combine: at most COMBINE by default (fewer when there are fewer candidates), else 1..count."""
    size = min(COMBINE, count) if max_size is None else max_size
    if not 1 <= size <= count:
        raise SceneError(f"--combine {size}: must be 1..{count} ({what})")
    return size


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


def _runs_table(fe: dict | None) -> str:
    """An FE design's specimen runs: each scene at each gauge length, run once at the card."""
    if not fe:
        return ""
    rows = "".join(f"<tr><td>{html.escape(Path(r['scene']).name)}</td><td>{html.escape(r['test'])}</td>"
                   f"<td>{html.escape(r['shape'])}</td><td>{r['gauge_length_mm']:.4g}</td><td>{r['dofs']}</td>"
                   f"<td>{_cell(r['end_strain'][0])}</td><td>{r['seconds']:.2f}{' (cache)' if r['from_cache'] else ''}"
                   f"</td></tr>" for r in fe["runs"])
    return (f"<h2>Specimen tests (FE in the loop)</h2><p>Constants {', '.join(map(html.escape, fe['parameters']))} "
            f"planned over the extensometer strain {fe['strain_range'][0]:.4g}..{fe['strain_range'][1]:.4g}; "
            f"extensometer scatter {fe['extensometer_std_mm']:.4g} mm; each scene run once at the card "
            f"({fe['seconds']:.1f} s in all, the fit included).</p><table><tr><th>scene</th><th>test</th>"
            f"<th>shape</th><th>gauge length (mm)</th><th>DOFs</th><th>end strain</th><th>run (s)</th></tr>"
            f"{rows}</table>")


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
            f"{_runs_table(d.get('fe'))}"
            f"<h2>Add one test to the present data</h2><table><tr><th>test</th>{se_h}{red_h}{tail}</tr>"
            f"{_rows(d['next'], names, True)}</table>"
            f"<h2>Candidate tests alone and combined</h2><table><tr><th>tests</th>{se_h}{tail}</tr>"
            f"{_rows(d['candidates'], names, False)}</table></body></html>")


def design_command(path: Path, out: Path | None, candidates: str | None, ranges: str | None, points: int,
                   max_size: int | None, noise: float | None, console: Console, force: bool = False,
                   expect: str | None = None, specimens: str | None = None, gauges: str | None = None,
                   elongation_sd: float | None = None, results: Console | None = None) -> int:
    """Errors and warnings on ``console`` (stderr), the verdicts and report path on ``results`` (stdout)."""
    from vlab.identify.command import _destination
    from vlab.identify.fitfile import load_fit
    from vlab.report.folder import ReportFolderError, report_folder

    def invalid(label, exc) -> int:
        return console.print(Text.assemble((label, "red"), f" {exc}"), highlight=False, soft_wrap=True) or 2

    try:
        spec = load_fit(path)
        spans = parse_ranges(ranges) if _points_ok(points) else {}
        if spec.fe is not None:
            kinds = () if candidates is None else parse_candidates(candidates)
            d = design_fe(spec, kinds, spans, points, max_size, noise, parse_expect(expect, spec.fe["parameters"]),
                          parse_list(specimens, "--specimens", "path"), parse_list(gauges, "--gauge-lengths", "mm"),
                          _elongation_sd(elongation_sd))
        else:
            if specimens is not None or gauges is not None or elongation_sd is not None or "specimen" in spans:
                raise SceneError("--specimens, --gauge-lengths, --extensometer-std and --range specimen=... plan "
                                 "FE-in-the-loop tests: "
                                 "they need a fit file with a data set of kind = \"specimen\" and an [fe] table")
            kinds = parse_candidates(candidates)
            d = design(spec, kinds, spans, points, _combine_size(max_size, len(kinds), "the number of candidate kinds"),
                       noise, parse_expect(expect, spec.model.names))
    except SceneError as exc:
        return invalid("invalid input", exc)
    try:
        dest = _destination(out or Path("reports") / f"{spec.name}-design", force, spec, path)
        with report_folder(dest, "design") as tmp:
            (tmp / "design.json").write_text(json.dumps(d, indent=2))
            (tmp / "index.html").write_text(page(d), encoding="utf-8")
    except ReportFolderError as exc:
        return invalid("invalid output folder", exc)
    _summary(d, dest.path / "index.html", console, results or console)
    return 0 if d["fit_converged"] is not False else 1


def _summary(d: dict, index: Path, console: Console, results: Console) -> None:
    """The summary: the present data's verdict, the answer, the best candidates and the report on
    ``results`` (stdout), warnings on ``console`` (stderr)."""
    results.print(Text(f"{d['name']}: {d['model']['name']}, present data {d['present_data']['verdict']}"),
                  highlight=False)
    for w in d["warnings"]:
        console.print(Text.assemble("  ", ("warning", "yellow"), f" {w}"), highlight=False, soft_wrap=True)
    results.print(Text(f"  next: {d['answer']}"), highlight=False, soft_wrap=True)
    for e in d["candidates"][:5]:
        results.print(Text(f"  {e['label']}: {e['verdict']}, D {_cell(e['D'])}, A {_cell(e['A'])}"), highlight=False)
    results.print(Text(f"report: {index}"), highlight=False, soft_wrap=True)
