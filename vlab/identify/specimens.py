"""Several specimens of one material: a fit per specimen, the pooled fit, and between-specimen
statistics of every fitted constant (fit.json → ``specimens``).

    [[data]]
    file = "specimen-B.csv"
    kind = "uniaxial"
    specimen = "B"          # any data set (any kind but "specimen", FE in the loop) may name one

When the data sets name two or more specimens, every data set must name one. The pooled fit (all
data sets together) is the fit and its card is the card; each specimen's data sets are also fitted
on their own by the same fit (vlab.identify.fitting.fit_any on the spec filtered to them). Over
the n specimen fits that converged, for each constant c_1..c_n:

    mean  m = Σ c_i / n,   standard deviation s = sqrt(Σ (c_i − m)² / (n − 1))   (sample, n − 1),
    coefficient of variation  cv = s / |m|,   and min, max, the pooled value and whether it lies
    in [min, max].

With n < 2 the standard deviation and cv are null with a reason (strict JSON: no NaN), as is cv
when m = 0. A file naming one specimen is fitted exactly as without it; fit.json says n = 1.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from vlab import fields
from vlab.fields import SceneError

__all__ = ["split_specimen", "check_specimens", "specimen_ids", "fit_specimens", "between_statistics"]

MAX_ID = 64
BAND_KINDS = ("uniaxial", "equibiaxial", "planar", "simple-shear")


def split_specimen(raw, i: int):
    """(the [[data]] table without ``specimen``, the checked id or None)."""
    if not isinstance(raw, dict) or "specimen" not in raw:
        return raw, None
    rest = {k: v for k, v in raw.items() if k != "specimen"}
    v = raw["specimen"]
    where = f"data[{i}].specimen"
    if not isinstance(v, str) or not v.strip():
        raise SceneError(f"{where} must be a specimen id (a non-empty string, e.g. \"B\"), got {fields.show(v)}")
    if len(v) > MAX_ID or not v.isprintable() or v != v.strip():
        raise SceneError(f"{where} must be a printable id of at most {MAX_ID} characters without leading or "
                         f"trailing spaces, got {fields.show(v)}")
    return rest, v


def specimen_ids(datasets) -> list[str]:
    """The specimen ids the data sets name, in the order they first appear."""
    return list(dict.fromkeys(d.specimen for d in datasets if d.specimen is not None))


def check_specimens(model, effects: dict, datasets, fe) -> None:
    """With two or more specimens: every data set names one, none is an FE-in-the-loop reading, and
    each specimen's data sets can be fitted on their own (a fitted set; what records need)."""
    ids = specimen_ids(datasets)
    if len(ids) < 2:
        return
    for i, d in enumerate(datasets):
        if d.specimen is None:
            raise SceneError(f"data[{i}] ({d.name!r}) names no specimen while others name {', '.join(map(repr, ids))}: "
                             "with several specimens every data set says whose it is (data.specimen = \"<id>\")")
        if d.kind == "specimen":
            raise SceneError(f"data[{i}].specimen: several specimens are fitted with the homogeneous states; a data "
                             "set of kind = \"specimen\" (FE in the loop) cannot be one of them")
    from vlab.identify.records import check_records

    for s in ids:
        own = [d for d in datasets if d.specimen == s]
        if not any(d.role == "fit" for d in own):
            raise SceneError(f"specimen {s!r} has no data set with role = \"fit\": each specimen is fitted on its own")
        try:
            check_records(model, effects, own, fe)
        except SceneError as exc:
            raise SceneError(f"specimen {s!r} (fitted on its own): {exc}") from None


def _constant_rows(d: dict) -> dict:
    """{constant: {value, standard_error, interval, reason}} of a fit dict."""
    return {k: {"value": u["value"], "standard_error": u["standard_error"], "interval": u["interval"],
                "reason": u["reason"]} for k, u in d["uncertainty"].items()}


def _specimen_record(o, sets) -> dict:
    d = o.data
    rms = [x["rms_relative"] for x in d["datasets"] if x["role"] == "fit"]
    return {"converged": d["converged"], "reason": d["reason"], "trustworthy": d["trust"]["trustworthy"],
            "datasets": [x.name for x in sets], "points": int(sum(x.points for x in sets)),
            "rms_relative": float(np.sqrt(np.mean(np.square(rms)))) if rms else None,
            "constants": _constant_rows(d)}


def between_statistics(values: list[float], pooled: float | None) -> dict:
    """mean, sample standard deviation (n − 1), cv = sd / |mean|, min, max, n of one constant's
    specimen values; a statistic that n or the mean does not define is null with its reason."""
    v = np.asarray([x for x in values if x is not None and np.isfinite(x)], float)
    n = len(v)
    out = {"n": n, "mean": None, "standard_deviation": None, "coefficient_of_variation": None,
           "min": None, "max": None, "pooled": pooled, "pooled_within_range": None, "reason": None}
    if n == 0:
        return out | {"reason": "no specimen fit converged with a value of this constant"}
    m = float(np.mean(v))
    out |= {"mean": m, "min": float(np.min(v)), "max": float(np.max(v))}
    if pooled is not None:
        out["pooled_within_range"] = bool(out["min"] <= pooled <= out["max"])
    if n < 2:
        return out | {"reason": "n = 1: one specimen gives no between-specimen spread"}
    s = float(np.std(v, ddof=1))
    out["standard_deviation"] = s
    if m == 0:
        return out | {"reason": "mean = 0: the coefficient of variation is not defined"}
    return out | {"coefficient_of_variation": s / abs(m)}


def _statistics(pooled: dict, records: dict) -> dict:
    """Per constant of the pooled fit: between_statistics over the converged specimen fits."""
    out = {}
    for k, u in pooled["uncertainty"].items():
        vals = [r["constants"][k]["value"] for r in records.values() if r["converged"] and k in r["constants"]]
        out[k] = between_statistics(vals, u["value"])
    return out


def _one_specimen(ids: list[str]) -> dict:
    return {"n": 1, "ids": ids, "per_specimen": None, "statistics": None,
            "reason": f"one specimen ({ids[0]!r}): no per-specimen fits or between-specimen statistics; the fit is "
                      "the fit of its data"}


def fit_specimens(spec, fit_one, execution=None):
    """The pooled FitOutcome of ``fit_one(spec, execution)`` with fit.json → ``specimens`` (one fit
    per specimen by the same ``fit_one`` on its data sets, and the statistics between them)."""
    ids = specimen_ids(spec.datasets)
    pooled = fit_one(spec, execution)
    if len(ids) < 2:
        if ids:
            pooled.data["specimens"] = _one_specimen(ids)
        return pooled
    outcomes, records = {}, {}
    for s in ids:
        own = tuple(d for d in spec.datasets if d.specimen == s)
        try:
            outcomes[s] = fit_one(dataclasses.replace(spec, name=f"{spec.name}-{s}", datasets=own), execution)
        except SceneError as exc:
            raise SceneError(f"specimen {s!r} (fitted on its own): {exc}") from None
        records[s] = _specimen_record(outcomes[s], own)
    d = pooled.data
    d["specimens"] = {"n": len(ids), "ids": ids, "per_specimen": records,
                      "statistics": _statistics(d, records), "reason": None,
                      "note": "mean and sample standard deviation (n − 1) over the specimen fits that converged; "
                              "cv = sd / |mean|; the pooled fit (all data sets) is the card, and its standard errors count "
                              "the scatter between specimens as noise"}
    _mark_datasets(d, spec.datasets)
    failed = [s for s, r in records.items() if not r["converged"]]
    if failed:
        d["warnings"].append(f"the fit of specimen(s) {', '.join(failed)} did not converge: the between-specimen "
                             "statistics leave them out (n counts the others)")
    _add_band_figure(pooled, spec, outcomes)
    return pooled


def _mark_datasets(d: dict, datasets) -> None:
    """fit.json's datasets[] rows get their specimen (matched by name and file)."""
    of = {(x.name, x.file): x.specimen for x in datasets}
    for row in d["datasets"]:
        if (row["name"], row["file"]) in of:
            row["specimen"] = of[(row["name"], row["file"])]


def band_panels(pooled, spec, outcomes: dict) -> list[dict]:
    """Per kind of BAND_KINDS in the data: the grid over the specimens' common range, each
    specimen's fitted curve on it (lo, hi: their envelope), the pooled fit, and the data."""
    from vlab.identify.datasets import Dataset
    from vlab.identify.solve import predict

    out = []
    for kind in BAND_KINDS:
        sets = [d for d in spec.datasets if d.kind == kind and d.b is None]
        if not sets:
            continue
        a = np.linspace(min(float(np.min(d.a)) for d in sets), max(float(np.max(d.a)) for d in sets), 120)
        measure = sets[0].measure
        grid = Dataset(kind, "", kind, "fit", 1.0, measure, a, None, np.zeros_like(a))
        curves = {s: np.real(predict(o.spec.model, o.x[None, :], grid)[0]) for s, o in outcomes.items()
                  if o.converged}
        if not curves:
            continue
        stack = np.array(list(curves.values()))
        out.append({"kind": kind, "measure": measure, "a": a, "lo": stack.min(0), "hi": stack.max(0),
                    "curves": curves, "pooled": np.real(predict(pooled.spec.model, pooled.x[None, :], grid)[0]),
                    "data": [(d.specimen, d.a, d.y) for d in sets if d.measure == measure]})
    return out


def record_band_panels(pooled, spec, outcomes: dict) -> list[dict]:
    """Per record kind in the data (relaxation, cyclic, DMA storage and loss): the first record of
    that kind is the reference history; each specimen's fitted model and the pooled fit are run
    over it (lo, hi: the specimens' envelope), drawn against its time (s) — a cyclic record without
    a time column against its row — or its frequency (Hz); each specimen's records are drawn
    against their own time, row or frequency."""
    from vlab.identify.records import KINDS

    out = []
    for kind in ("relaxation", "cyclic", "dma"):
        sets = [d for d in spec.datasets if d.kind == kind]
        if not sets:
            continue
        ref = sets[0]
        run = lambda o: np.real(KINDS[kind].predict(o.spec.model, o.spec.effects, o.x[None, :], ref)[0])  # noqa: E731
        curves = {s: run(o) for s, o in outcomes.items() if o.converged}
        if not curves:
            continue
        pooled_y, stack = run(pooled), np.array(list(curves.values()))
        axis, label = _record_axis(ref)
        halves = (("storage", 0), ("loss", 1)) if kind == "dma" else ((None, None),)
        for part, j in halves:
            pick = (lambda y: np.split(y, 2)[j]) if part else (lambda y: y)  # noqa: E731
            out.append({"kind": kind if part is None else f"DMA {part} ({ref.extra['modulus']})",
                        "measure": "nominal", "a": axis, "xlabel": label, "log_x": kind == "dma",
                        "ylabel": f"{part} modulus (MPa)" if part else "nominal stress (MPa)",
                        "lo": pick(stack.min(0)), "hi": pick(stack.max(0)),
                        "curves": {k: pick(v) for k, v in curves.items()}, "pooled": pick(pooled_y),
                        "data": [(d.specimen, _record_axis(d)[0], pick(d.y)) for d in sets]})
    return out


def _record_axis(d) -> tuple[np.ndarray, str]:
    """The x of a record's points: time (s), the row of a cyclic record without time, frequency (Hz)."""
    if d.kind == "relaxation":
        return d.a, "time (s)"
    if d.kind == "dma":
        return d.a, "frequency (Hz)"
    mask = d.extra["mask"]
    if d.extra["time"] is not None:
        return d.extra["time"][mask], "time (s)"
    return np.nonzero(mask)[0] + 1.0, "row of the history"


def _add_band_figure(pooled, spec, outcomes: dict) -> None:
    """specimens.png (the band of the specimens' fitted curves — equilibrium curves, or records run
    over a reference history — with the pooled fit), or why not."""
    spec_d = pooled.data["specimens"]
    panels = band_panels(pooled, spec, outcomes) + record_band_panels(pooled, spec, outcomes)
    if not panels:
        spec_d["figure"], spec_d["figure_reason"] = None, (f"no data set of kind {', '.join(BAND_KINDS)} or a "
                                                           "record (relaxation, cyclic, dma)")
        return
    from vlab.identify.plots import plot_specimens

    spec_d["figure"], spec_d["figure_reason"] = "specimens.png", None
    caption = (f"The {len(outcomes)} specimens' fitted curves (grey band: their envelope; thin lines: each "
               "specimen) with their data (points) and the pooled fit (black). A record's band is each "
               "specimen's fitted model run over the first record of its kind (the reference history).")
    pooled.extras.setdefault("figures", []).append(("specimens.png", caption))
    pooled.extras.setdefault("writers", []).append(("specimens.png", lambda p: plot_specimens(spec.name, panels, p)))
