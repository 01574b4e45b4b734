"""The budget of a scene: paired runs (GUM) and Monte Carlo samples as sweeps, then the analysis.

Two sweeps through vlab.study.sweep (Dask, the content-hash cache, so an interrupted budget
resumes with the runs it finished): first the nominal run and, for every input that changes the
FE run, the pair at ±u (inputs that act only on the analysis reuse the nominal run); then the
Monte Carlo samples, each a full virtual test (vlab.uncertainty.model), with the readings
quantised at the resolution the nominal run's force level sets.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from vlab.study.grid import GridPoint
from vlab.uncertainty.analysis import gum_budget, monte_carlo, sobol_first_order
from vlab.uncertainty.model import lab_values, resolutions, sample_deltas, scene_source
from vlab.uncertainty.spec import UncertaintySpec

__all__ = ["BudgetRuns", "BudgetError", "compute_budget", "QUANTITIES"]

#: budget.json's quantities, in lab_values' order: the extensometer's E and ν, the crosshead's E
QUANTITIES = ("E", "nu", "E_crosshead")

#: runner(points, what) -> vlab.study.sweep.SweepOutcome (the CLI's sweep with a progress bar)
Runner = Callable[[list, str], object]


class BudgetError(RuntimeError):
    """The nominal run failed: there is no budget of a test that does not run."""


@dataclass
class BudgetRuns:
    deltas: list[dict]
    summaries: list[dict]
    E: list
    nu: list
    E_crosshead: list


def _paired_points(source, spec: UncertaintySpec, base_dir: str) -> tuple[list, dict]:
    points = [GridPoint({"run": "nominal"}, scene_source(source, spec, {}), base_dir)]
    index = {}
    for s in (s for s in spec.sources if s.fe):
        for sign, tag in ((1.0, "+"), (-1.0, "-")):
            index[(s.name, tag)] = len(points)
            points.append(GridPoint({"run": f"{s.name} {tag}u"}, scene_source(source, spec, {s.name: sign * s.u}),
                                    base_dir))
    return points, index


def _gum(spec, summaries, index, which: int) -> tuple[list[dict], float]:
    plus, minus = [], []
    nominal = summaries[0]["measured"]
    for s in spec.sources:
        vals = []
        for sign, tag in ((1.0, "+"), (-1.0, "-")):
            run = summaries[index[(s.name, tag)]] if s.fe else summaries[0]
            ok = run["status"] == "ok"
            vals.append(lab_values(run["measured"] if ok else nominal, spec, {s.name: sign * s.u})[which]
                        if ok else None)
        plus.append(vals[0])
        minus.append(vals[1])
    return gum_budget(spec.sources, plus, minus)


def _quantity(name, spec, rows, u_gum, y, X, nominal_value, seed) -> dict | None:
    y = np.asarray([v for v in y if v is not None], float)
    if nominal_value is None or not len(y):
        return None
    mc = monte_carlo(y)
    sob = sobol_first_order(X, y, seed) if len(X) == len(y) and len(y) > 1 else [(None, None)] * len(rows)
    contributions = []
    for r, (s, e) in zip(rows, sob):
        contributions.append({**r, "sobol": None if s is None or not np.isfinite(s) else s,
                              "sobol_error": None if e is None or not np.isfinite(e) else e})
    contributions.sort(key=lambda r: -(r["share"] or 0.0))
    ratio = u_gum / mc["u"] if mc["u"] > 0 else None
    return {"quantity": name, "nominal": nominal_value, **mc, "gum": {"u": u_gum, "U": 2.0 * u_gum, "k": 2.0},
            "gum_over_monte_carlo": ratio, "contributions": contributions}


def _bending(nominal: dict, summaries: list[dict]) -> dict | None:
    """The ASTM E1012 percent bending at the gauge centre (a budget with alignment entries): the
    nominal run's, and the samples' mean, standard deviation and largest |B|; None without."""
    if nominal["measured"].get("percent_bending") is None and not any(
            s["status"] == "ok" and s["measured"].get("percent_bending") is not None for s in summaries):
        return None

    def stats(key: str) -> dict:
        b = np.array([s["measured"][key] for s in summaries
                      if s["status"] == "ok" and s["measured"].get(key) is not None], float)
        return {"nominal": nominal["measured"].get(key), "mean": float(b.mean()) if len(b) else None,
                "u": float(b.std(ddof=1)) if len(b) > 1 else None,
                "max_abs": float(np.abs(b).max()) if len(b) else None}

    return stats("percent_bending") | {
        "thickness_plane": stats("percent_bending_thickness"), "width_plane": stats("percent_bending_width"),
        "definition": "ASTM E1012, four gauges at the gauge centre: sqrt(b_y^2 + b_z^2) / a x 100; each plane's "
                      "pair signed: (e1 - e2) / (e1 + e2) x 100"}


def compute_budget(source: dict, spec: UncertaintySpec, base_dir: str | Path, runner: Runner,
                   window_lo: float) -> tuple[dict, BudgetRuns]:
    """budget.json's dict and the samples' runs (``runner`` executes a list of GridPoints)."""
    base_dir = str(Path(base_dir).resolve())
    points, index = _paired_points(source, spec, base_dir)
    paired = runner(points, "paired")
    nominal = paired.summaries[0]
    if nominal["status"] != "ok" or nominal["measured"].get("E") is None:
        raise BudgetError(f"the nominal run did not give E ({nominal['status']}: {nominal.get('diagnosis')})")
    res = resolutions(spec, nominal["measured"]["E"], window_lo)
    noise_seed = int((source.get("effects", {}).get("noise") or {}).get("seed", 0))
    deltas = [sample_deltas(spec, i) for i in range(spec.samples)]
    mc_points = [GridPoint({"sample": i}, scene_source(source, spec, d, res | {"seed": noise_seed + i} if res else None),
                           base_dir) for i, d in enumerate(deltas)]
    mc = runner(mc_points, "samples")
    values = [lab_values(s["measured"], spec, d) if s["status"] == "ok" else (None, None, None)
              for s, d in zip(mc.summaries, deltas)]
    ok = [i for i, v in enumerate(values) if v[0] is not None]
    X = np.array([[deltas[i][s.name] for s in spec.sources] for i in ok]).reshape(len(ok), len(spec.sources))
    nominal_lab = lab_values(nominal["measured"], spec, {})
    out = {"samples": spec.samples, "seed": spec.seed, "failed_samples": spec.samples - len(ok),
           "resolution": res, "nominal_dimensions": spec.nominal,
           "load_cell": spec.load_cell, "extensometer": spec.extensometer, "micrometer": spec.micrometer,
           "inputs": [{"input": s.name, "distribution": s.distribution, "half_width": s.half_width, "u": s.u,
                       "unit": s.unit, "source": s.source, "changes_the_run": s.fe} for s in spec.sources],
           "runs": {"paired": len(points), "samples": len(mc_points),
                    "cache_hits": paired.cache_hits + mc.cache_hits, "computed": paired.computed + mc.computed,
                    "seconds": {"paired": paired.seconds, "samples": mc.seconds}}}
    out["percent_bending"] = _bending(nominal, mc.summaries)
    for which, name in enumerate(QUANTITIES):
        rows, u_gum = _gum(spec, paired.summaries, index, which)
        ys = [values[i][which] for i in ok]
        Xq = X if all(v is not None for v in ys) else X[[j for j, v in enumerate(ys) if v is not None]]
        out[name] = _quantity(name, spec, rows, u_gum, ys, Xq, nominal_lab[which], spec.seed)
    return out, BudgetRuns(deltas, mc.summaries, *([v[k] for v in values] for k in range(len(QUANTITIES))))
