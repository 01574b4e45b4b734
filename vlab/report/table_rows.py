"""The rows of the report tables: a run's summary (``summary_rows``) and the comparison page's models
table (``comparison_rows``: one value per model), every value as measured in the results dicts
(vlab.report.html lays them out; nothing here computes physics)."""

from __future__ import annotations

import html
from typing import TYPE_CHECKING

import numpy as np

from vlab.report.explain import by_design_notes
from vlab.report.kind_rows import kind_of_data, kind_rows

if TYPE_CHECKING:
    from vlab.report.html import ReportPage

__all__ = ["summary_rows", "comparison_rows", "cruciform_rows"]


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
    text = f"{text}; {_fmt(solver.get('tangent_kernel'))}"
    choice = linear.get("choice") or ""
    if "free DOFs ≥" in choice:  # above the DOF crossover: say what decided the path
        text += f"<br><small class=why>{html.escape(choice)}</small>"
    return text



def _why(notes: dict, key: str) -> str:
    """The reason a measured constant differs from its input by design, set under the number."""
    return f"<br><small class=why>{html.escape(notes[key])}</small>" if key in notes else ""



def summary_rows(data: dict) -> list[tuple[str, str]]:
    """(quantity, value) rows of one run's summary, every value as measured."""
    m, inp, solver, mesh = data["measured"], data["input"], data["solver"], data["mesh"]
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
        ("wall time [s]", _fmt(data["timing"]["total_s"], 3)),
    ]
    if m.get("E_fit"):
        rows.append(("E fit", f"{m['E_fit']['method']} over |strain| {m['E_fit']['window']}, "
                              f"{m['E_fit']['n_points']} points, R² = {m['E_fit']['r2']:.6f}"))
    return (rows + _noisy_rows(m) + _stability_rows(data.get("stability") or [])
            + cruciform_rows(data.get("cruciform")) + _reference_rows(data.get("reference") or {}))



def _noisy_rows(m: dict) -> list[tuple[str, str]]:
    """effects.noise: the interval and the value the exact instruments would read."""
    unc, rows = m.get("uncertainty") or {}, []
    for key, unit in (("E", " [MPa]"), ("nu", "")):
        iv = unc.get(key)
        if iv:
            rows.append((f"{'ν' if key == 'nu' else 'E'} {100 * iv['confidence']:g} % interval{unit}",
                         f"[{_fmt(iv['low'])}, {_fmt(iv['high'])}] from {iv['n_points']} noisy points; "
                         f"noiseless {_fmt(unc['noiseless'][key])}"))
    return rows



def _stability_rows(stab: list[dict]) -> list[tuple[str, str]]:
    """How many levels the inertia of K_ff found stable, and where the first unstable one was."""
    if not stab:
        return []
    unstable = [r for r in stab if not r["accepted"]]
    return [("stability (inertia of K_ff)",
             f"{len(stab) - len(unstable)} of {len(stab)} levels stable (no negative eigenvalue)"
             + (f"; stopped at stretch {unstable[0]['stretch']}: "
                f"{unstable[0]['negative_eigenvalues']} negative eigenvalue(s), "
                f"limit point {unstable[0]['limit_point']}" if unstable else ""))]



def _reference_rows(ref: dict) -> list[tuple[str, str]]:
    return [(f"stress vs analytic ({k[-1]})", f"max relative error {_fmt(v, 3)}")
            for k, v in ref.items() if k.startswith("max_relative_error")]



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



def _model_status(data: dict) -> str:
    if data["converged"]:
        return "<span class=ok>completed</span>"
    f = data["failure"]
    load = kind_of_data(data).load_key
    return (f"<span class=fail>stopped at step {f['step']}, {load} {_fmt(f['stretch'])}: "
            f"{html.escape(f['reason'])}</span>")



def comparison_rows(page: ReportPage) -> list[tuple[str, list[str]]]:
    """(quantity, value per model) rows of the models table, every value as measured."""
    kind = kind_of_data(page.models[0])

    def per(fn):
        return [fn(d) for d in page.models]

    rows = [
        ("status", per(_model_status)),
        *(_elastic_rows(per) if kind.measures_E else []),
        *kind_rows(page.models),
        (f"force at max {kind.load_key} [N]", per(lambda d: _peak_force(kind, d))),
        *(_departure_rows(page, per) if kind.lateral_ratio and page.departures else []),  # nothing compared: no rows
        ("stress vs analytic, max rel. error", per(_max_reference_error)),
        *_cost_rows(per),
    ]
    if any(d.get("accuracy_estimate") for d in page.models):
        rows.append(("accuracy estimate (coarser companion solve)", per(_estimate)))
    return rows + _per_model_cruciform_rows(page.models) + _interval_rows(page.models) + _taylor_rows(page)



def _elastic_rows(per) -> list[tuple[str, list[str]]]:
    """E and ν measured against their input, and the E fit's R² (kinds that measure E)."""
    return [
        ("E measured [MPa]", per(lambda d: _measured_E(d) + _why(by_design_notes(d), "E"))),
        ("E input [MPa]", per(lambda d: _fmt(d["input"]["E"]))),
        ("ν measured", per(lambda d: _fmt(d["measured"]["nu"]) + _why(by_design_notes(d), "nu"))),
        ("ν input", per(lambda d: _fmt(d["input"]["nu"]))),
        ("E fit R²", per(lambda d: _fmt((d["measured"].get("E_fit") or {}).get("r2"), 8))),
    ]



def _peak_force(kind, d: dict) -> str:
    """The load cell at the largest |control − rest| (cyclic tests end at rest) and where."""
    forces, control = d["curve"][kind.force_column], d["curve"][kind.control_column]
    if not forces:
        return "—"
    rest = 1.0 if kind.load_key == "stretch" else 0.0
    peak = int(np.argmax(np.abs(np.asarray(control, dtype=float) - rest)))
    return f"{_fmt(forces[peak])} at {'grip stretch' if rest else 'shear'} {_fmt(control[peak], 4)}"



def _max_reference_error(d: dict) -> str:
    ref = d.get("reference") or {}
    errors = [v for k, v in ref.items() if k.startswith("max_relative_error") and v is not None]
    return _fmt(max(errors), 3) if errors else "—"



def _departure_rows(page: ReportPage, per) -> list[tuple[str, list[str]]]:
    """The strains where each model's stress departs from Neo-Hookean's by 5 and 10 %."""
    def departure(key):
        return lambda d: _fmt((page.departures.get(d["input"].get("label", d["input"]["model"])) or {}).get(key), 4)

    return [("strain where |s − s_NH|/s_NH ≥ 5 %", per(departure("5%"))),
            ("strain where |s − s_NH|/s_NH ≥ 10 %", per(departure("10%")))]



def _cost_rows(per) -> list[tuple[str, list[str]]]:
    """What each run cost (iterations, solvers, cutbacks, time) and on which mesh."""
    return [
        ("Newton iterations (total)", per(lambda d: _newton_cost(d["solver"]))),
        ("linear solver; tangent kernel", per(lambda d: _solvers(d["solver"]))),
        ("cutbacks", per(lambda d: _fmt(sum(d["solver"]["cutbacks"])))),
        ("wall time [s]", per(lambda d: _fmt(d["timing"]["total_s"], 3))),
        ("DOFs", per(lambda d: _fmt(d["mesh"]["dofs"]))),
        ("mesh", per(lambda d: f"{d['mesh']['elements']} {d['mesh']['cell']} (order {d['mesh']['order']})"
                     + (f", {d['mesh']['symmetry']} model" if d["mesh"].get("symmetry", "none") != "none" else ""))),
        ("mesh quality", per(lambda d: _quality(d["mesh"].get("quality")))),
    ]



def _interval_rows(models: list[dict]) -> list[tuple[str, list[str]]]:
    """effects.noise: the confidence intervals of E and ν from the noisy instruments."""
    rows = []
    for key, name in (("E", "E [MPa]"), ("nu", "ν")):
        cells = [(d["measured"].get("uncertainty") or {}).get(key) for d in models]
        if any(cells):
            conf = next(c for c in cells if c)["confidence"]
            rows.append((f"{name} {100 * conf:g} % interval (noisy instruments)",
                         [f"[{_fmt(c['low'])}, {_fmt(c['high'])}]" if c else "—" for c in cells]))
    return rows



def _taylor_rows(page: ReportPage) -> list[tuple[str, list[str]]]:
    taylor = [page.checks.get(d["input"].get("label", d["input"]["model"]), {}).get("taylor") for d in page.models]
    if not any(taylor):
        return []
    return [("Taylor test order: energy / force (2 = consistent)",
             [f"{t['energy_order']:.3f} / {t['force_order']:.3f}" if t else "—" for t in taylor])]



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
    if "E" in by_design_notes(d):  # the other number that looks like an error and is not one
        text += (". This is the discretisation error of the FE answer only; E differs from its input for "
                 "the reason under the E row")
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



def _measured_E(d: dict) -> str:
    """E, or — with the reason it was not measured (e.g. the material yields before the window)."""
    m = d["measured"]
    if m["E"] is None and m.get("note"):
        return f"— <small>({html.escape(m['note'])})</small>"
    return _fmt(m["E"])
