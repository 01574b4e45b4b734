"""The fit of lab records (relaxation, DMA, cycles) with any homogeneous curves: a hyperelastic
ground law and, with [model] viscoelastic, a Prony series, with [model] mullins the Ogden–Roxburgh
softening, or both together (cyclic.stress_along) — one least-squares problem.

Internal coordinates x = [the law's x, β_0..β_{N−1}, τ_0..τ_{N−1} (when fitted), r, m,
mullins_beta (when fitted)]; the card values are c = T x with T = diag(the law's T, I). Residuals are relative (or absolute) per point
as in solve.py, a DMA record's storage and loss each with their own floor (1 % of its largest).
Equilibrium curves (uniaxial, planar, …) are the ground law's long-term response. Every
Jacobian is the exact complex step through the whole history (prony.py). Starts: the law's
sampler around a modulus estimate from the data; β_i log-uniform in [0.05, 1]; τ_i spread
log-evenly over the time scales the records resolve, jittered; bounds β ∈ [0, 1e4],
τ ∈ [t_min / 100, 100 t_max].
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from scipy.optimize import least_squares

from vlab.fields import SceneError
from vlab.identify import uncertainty as unc
from vlab.identify.card import card_of, card_toml
from vlab.identify.jacobian import value_and_jacobian
from vlab.identify.records import KINDS
from vlab.identify.records.prony import mu0_of, principal
from vlab.identify.solve import StartResult, max_I1, modulus_scale, predict, summarize_starts

__all__ = ["fit_records", "RecordObjective", "has_records"]


def has_records(spec) -> bool:
    return any(d.kind in KINDS for d in spec.datasets) or any(v is not None for v in spec.effects.values())


def _floors(d) -> np.ndarray:
    """Per point: max(|y|, 1 % of the largest |y| of its block) (a DMA record: storage, loss)."""
    blocks = np.split(np.abs(d.y), 2) if d.kind == "dma" else [np.abs(d.y)]
    out = [np.maximum(b, 0.01 * np.max(b)) for b in blocks]
    return np.where(np.concatenate(out) > 0, np.concatenate(out), 1.0)


class RecordObjective:
    """r(x) over records and homogeneous curves, and its complex-step Jacobian."""

    def __init__(self, model, effects: dict, datasets, residual: str = "relative"):
        self.model, self.effects, self.datasets = model, effects, list(datasets)
        self.prony, self.mullins = effects.get("viscoelastic"), effects.get("mullins")
        self.y = np.concatenate([d.y for d in self.datasets])
        scale = [(_floors(d) if residual == "relative" else np.ones_like(d.y)) for d in self.datasets]
        self.factor = np.concatenate([np.sqrt(d.weight) / s for d, s in zip(self.datasets, scale)])

    def predict(self, X, d):
        if d.kind in KINDS:
            return KINDS[d.kind].predict(self.model, self.effects, X, d)
        return predict(self.model, X, d)

    def __call__(self, X):
        pred = np.concatenate([self.predict(X, d) for d in self.datasets], axis=-1)
        return (pred - self.y) * self.factor

    def residual(self, x):
        with np.errstate(all="ignore"):
            r = np.real(self(np.asarray(x, float)[None, :])[0])
        return np.where(np.isfinite(r), r, 1e10)

    def jacobian(self, x):
        with np.errstate(all="ignore"):
            _, Jr = value_and_jacobian(self, x)
        return np.where(np.isfinite(Jr), Jr, 0.0)


def _time_window(datasets) -> tuple[float, float]:
    ranges = [r for r in (KINDS[d.kind].time_range(d) for d in datasets if d.kind in KINDS) if r is not None]
    if not ranges:
        raise SceneError("model.viscoelastic needs a timed record to fit (kind = \"relaxation\" or \"dma\"): "
                         "an equilibrium curve carries no relaxation time")
    return min(r[0] for r in ranges), max(r[1] for r in ranges)


def _scale(datasets) -> float:
    hom = [d for d in datasets if d.kind not in KINDS]
    values = [modulus_scale(hom)] if hom else []
    values += [KINDS[d.kind].scale(d) for d in datasets if d.kind in KINDS]
    values = [v for v in values if v > 0 and np.isfinite(v)]
    return float(np.median(values)) if values else 1.0


def _i1(datasets) -> float:
    out = max_I1([d for d in datasets if d.kind not in KINDS])
    for d in (d for d in datasets if d.kind in ("relaxation", "cyclic")):
        l1, l2, l3, _ = principal(d.extra["test"], d.b if d.kind == "relaxation" else d.extra["stretch"])
        out = max(out, float(np.max(l1 ** 2 + l2 ** 2 + l3 ** 2)))
    return out


def _start(rng, model, effects, scale, i1, window):
    """(x0, lo, hi) in the order x = [the law's, β_i, τ_i (when fitted), r, m, mullins_beta]."""
    x0, lo, hi = model.law.start(rng, scale, i1)
    prony, mullins = effects.get("viscoelastic"), effects.get("mullins")
    if prony is not None:
        N = prony.terms
        b0 = np.exp(rng.uniform(np.log(0.05), np.log(1.0), N))
        x0, lo, hi = np.r_[x0, b0], np.r_[lo, np.zeros(N)], np.r_[hi, np.full(N, 1e4)]
        if prony.tau is None:
            t_lo, t_hi = window
            grid = np.geomspace(t_lo, t_hi, N + 2)[1:-1] if N > 0 else []
            t0 = np.asarray(grid) * np.exp(rng.uniform(-0.5, 0.5, N))
            x0, lo, hi = np.r_[x0, t0], np.r_[lo, np.full(N, t_lo / 100)], np.r_[hi, np.full(N, 100 * t_hi)]
    if mullins is not None:  # r in (1.2, 4); m a fraction of the largest energy; β small
        w_top = 0.5 * scale * (i1 - 3.0)
        x0 = np.r_[x0, rng.uniform(1.2, 4.0), w_top * np.exp(rng.uniform(np.log(0.05), np.log(1.0)))]
        lo, hi = np.r_[lo, 1.0 + 1e-9, 1e-12], np.r_[hi, np.inf, np.inf]
        if mullins.beta is None:
            x0, lo, hi = np.r_[x0, rng.uniform(0.0, 0.3)], np.r_[lo, 0.0], np.r_[hi, np.inf]
    return x0, lo, hi


def _canonical(x, model, prony):
    """Prony terms in rising τ (interchangeable terms, one order), the law's own order first;
    the Prony entries follow the law's, the Mullins ones (if any) stay last."""
    n = len(model.law.names)
    order = np.r_[model.law.canonical_order(x[:n]), np.arange(n, len(x))]
    if prony is not None and prony.tau is None:
        N = prony.terms
        k = np.argsort(x[n + N:n + 2 * N])
        order[n:n + 2 * N] = np.r_[n + k, n + N + k]
    return order


def _one_start(obj, x0, lo, hi, max_nfev):
    with np.errstate(invalid="ignore"):  # inf − inf on an open side
        inside_lo, inside_hi = _inside(lo, hi)
    x0 = np.clip(x0, inside_lo, inside_hi)
    sol = least_squares(obj.residual, x0, jac=obj.jacobian, bounds=(lo, hi), method="trf", x_scale="jac",
                        max_nfev=max_nfev, ftol=1e-12, xtol=1e-12, gtol=1e-12)
    order = _canonical(sol.x, obj.model, obj.prony)  # (mullins' entries stay in place)
    return StartResult(x0, sol.x[order], float(sol.cost), int(sol.status), str(sol.message), int(sol.nfev),
                       tuple(bool(a) for a in (sol.active_mask != 0)[order]))


def _inside(lo, hi):
    """Starts kept just inside the box (least_squares needs a strictly feasible x0)."""
    return (np.where(np.isfinite(lo), lo + 1e-9 * np.maximum(1.0, np.abs(lo)), -np.inf),
            np.where(np.isfinite(hi), hi - 1e-9 * np.maximum(1.0, np.abs(hi)), np.inf))


class _Flat:
    """summarize_starts' view of the parameters: the card values of the whole vector."""

    def __init__(self, T):
        self.T = T

    def card_vector(self, x):
        return self.T @ np.asarray(x, float)


def _extra_names(effects) -> list[str]:
    return [n for k in ("viscoelastic", "mullins") if effects.get(k) is not None for n in effects[k].names]


def _transform(model, effects) -> np.ndarray:
    T = model.law.transform
    m = len(_extra_names(effects))
    return np.block([[T, np.zeros((len(T), m))], [np.zeros((m, len(T))), np.eye(m)]]) if m else T


def _errors(obj, x, d) -> dict:
    pred = np.real(obj.predict(np.asarray(x, float)[None, :], d)[0])
    rel = (pred - d.y) / _floors(d)
    out = {"name": d.name, "file": d.file, "kind": d.kind, "role": d.role, "weight": d.weight, "points": d.points,
           "range": [float(np.min(d.a)), float(np.max(d.a))], "rms_relative": float(np.sqrt(np.mean(rel ** 2))),
           "max_relative": float(np.max(np.abs(rel))), "rms_absolute_MPa": float(np.sqrt(np.mean((pred - d.y) ** 2)))}
    if d.kind == "relaxation":
        out |= {"test": d.extra["test"], "range_of": "time (s)"}
    elif d.kind == "cyclic":
        out |= {"test": d.extra["test"], "branch": d.extra["branch"], "range_of": "stretch"}
    elif d.kind == "dma":
        out |= {"modulus": d.extra["modulus"], "range_of": "frequency (Hz)"}
        for j, part in enumerate(("storage", "loss")):
            r = np.split(rel, 2)[j]
            out[f"{part}_rms_relative"] = float(np.sqrt(np.mean(r ** 2)))
    else:
        from vlab.identify.fitting import _cleanup
        out |= {"stress_measure": d.measure} | _cleanup(d)
    return out


def _prony_values(prony, x, n: int):
    """β and τ of the card values x (the law's n first, then β_i, τ_i)."""
    if prony is None:
        return {}
    N = prony.terms
    if prony.tau is None:
        return {"beta": x[n:n + N], "tau": x[n + N:n + 2 * N]}
    return {"beta": x[n:n + N], "tau": np.asarray(prony.tau, float)}


def _card(model, values_law, effects_values: dict) -> dict:
    """The [material] card and the [effects.*] tables `vlab run` reads, 6 significant digits."""
    card = card_of(model, values_law)
    if not effects_values:
        return card
    six = lambda v: [float(f"{x:.6g}") for x in v] if isinstance(v, (list, np.ndarray)) else float(f"{v:.6g}")  # noqa: E731
    tables = {k: {n: six(v) for n, v in t.items()} for k, t in effects_values.items()}
    text = "".join("\n" + card_toml(t).replace("[material]", f"[effects.{k}]") for k, t in tables.items())
    return card | {"effects": tables, "toml": card["toml"] + text}


def _mullins_values(mullins, values) -> dict:
    if mullins is None:
        return {}
    k = len(mullins.names)
    beta = values[-1] if mullins.beta is None else mullins.beta
    return {"r": float(values[-k]), "m": float(values[-k + 1]), "beta": float(beta)}


def _warnings(spec, prony, rows, best, names, pairs, starts) -> list[str]:
    out = []
    if spec.effects.get("mullins") is None:
        for d, r in zip(spec.datasets, rows):
            if d.kind == "cyclic" and KINDS["cyclic"].below_maximum(d):
                out.append(f"data set {r['name']!r} unloads and reloads below its earlier maximum, fitted without "
                           f"[model] mullins: the ground law has no softening, rms misfit {100 * r['rms_relative']:.3g} % "
                           f"(max {100 * r['max_relative']:.3g} %); if the reloads fall below the first loading, "
                           "add mullins = true")
    if prony is None:
        for r in rows:
            if r["kind"] == "relaxation":
                out.append(f"data set {r['name']!r} is a relaxation record fitted without [model] viscoelastic: "
                           f"the elastic ground law cannot relax, rms misfit {100 * r['rms_relative']:.3g} % "
                           f"(max {100 * r['max_relative']:.3g} %); add viscoelastic = {{ terms = 2 }}")
    if pairs:
        out.append("parameters not identifiable from the data given (" + ", ".join(
            f"|corr({a}, {b})| = {abs(c):.4f}" for a, b, c in pairs[:3]) + ")")
    if not starts["agree"]:
        out.append(f"the starts disagree: {starts['reached_best']} of {starts['count']} reached the best objective")
    bound = [n for n, b in zip(names, best.at_bound) if b]
    if bound:
        out.append(f"parameters on a bound of the admissible box: {', '.join(bound)} (their intervals assume an "
                   "interior optimum)")
    return out


def fit_records(spec):
    """The FitOutcome of a fit file with records (and/or [model] viscoelastic)."""
    from vlab.identify.fitting import FitOutcome, _information, _model_record, _stability, _verdict, trust_of

    t0 = time.perf_counter()
    model, effects = spec.model, spec.effects
    fit_sets = [d for d in spec.datasets if d.role == "fit"]
    obj = RecordObjective(model, effects, fit_sets, spec.residual)
    results = _run_starts(spec, obj, fit_sets)
    t_fit = time.perf_counter() - t0
    best = results[0]
    x = best.x
    r, J = obj.residual(x), obj.jacobian(x)
    cov_x, s2, dof, cond = unc.covariance(J, r)
    T = _transform(model, effects)
    names = list(model.law.names) + _extra_names(effects)
    values = T @ x
    stats = unc.summarize(values, T @ cov_x @ T.T, names, dof, spec.confidence)
    n = len(model.law.names)
    mu0 = model.law.mu0(values[:n])
    converged, reason = _verdict(best, mu0, spec.max_evaluations)
    starts = summarize_starts(results, _Flat(T))
    everything = RecordObjective(model, effects, spec.datasets, spec.residual)
    rows = [_errors(everything, x, d) for d in spec.datasets]
    params, tables = _card_entries(model, effects, values)
    hom = dataclasses.replace(spec, datasets=tuple(d for d in spec.datasets if d.kind not in KINDS))
    data = {
        "name": spec.name, "converged": bool(converged), "reason": reason,
        "model": _model_record(model, mu0) | _effects_record(effects),
        "parameters": params, "uncertainty": stats["uncertainty"], "confidence": spec.confidence,
        "correlation": stats["correlation"], "datasets": rows,
        "information": _information(r, len(x), s2, dof), "starts": starts,
        "identifiability": _identifiability(stats, cond),
        "stability": _stability(model, x, hom), "card": _card(model, values[:n], tables),
        "warnings": _warnings(spec, effects.get("viscoelastic"), rows, best, names, stats["correlated_pairs"], starts),
        "options": {"residual": spec.residual, "starts": spec.starts, "seed": spec.seed},
        "timing": {"fit_s": t_fit, "total_s": time.perf_counter() - t0},
    }
    data["trust"] = trust_of(data)
    return _with_figures(FitOutcome(data, hom, x, cov_x, stats["t_quantile"]), everything, spec)


def _run_starts(spec, obj: RecordObjective, fit_sets) -> list:
    """The StartResult of every start (spec.starts of them, drawn in turn from default_rng(spec.seed)),
    the lowest cost first."""
    model, effects = spec.model, spec.effects
    window = _time_window(fit_sets) if effects.get("viscoelastic") is not None else (1.0, 1.0)
    rng = np.random.default_rng(spec.seed)
    scale, i1 = _scale(fit_sets), _i1(fit_sets)
    return sorted((_one_start(obj, *_start(rng, model, effects, scale, i1, window), spec.max_evaluations)
                   for _ in range(spec.starts)), key=lambda r: r.cost)


def _card_entries(model, effects: dict, values) -> tuple[dict, dict]:
    """(fit.json's parameters: the law's card constants, then Prony β and τ, then Mullins r, m and
    mullins_beta; the [effects.*] tables of the card) of the fitted card values."""
    prony, mullins = effects.get("viscoelastic"), effects.get("mullins")
    n = len(model.law.names)
    pv = _prony_values(prony, values, n)
    params = {k: v for k, v in model.law.card(values[:n]).items() if k != "model"}
    if prony is not None:
        params |= {"beta": [float(v) for v in pv["beta"]], "tau": [float(v) for v in pv["tau"]]}
    mv = _mullins_values(mullins, values)
    if mullins is not None:
        params |= {"r": mv["r"], "m": mv["m"], "mullins_beta": mv["beta"]}
    tables = ({"viscoelastic": {"tau": list(pv["tau"]), "beta": list(pv["beta"])}} if prony is not None else {}) | (
        {"mullins": mv} if mullins is not None else {})
    return params, tables


def _effects_record(effects: dict) -> dict:
    """fit.json's model entries of the effects: the Prony terms (and fixed τ), the fixed Mullins β."""
    prony, mullins = effects.get("viscoelastic"), effects.get("mullins")
    return {"viscoelastic": None if prony is None else {"terms": prony.terms, "tau_fixed": prony.tau},
            "mullins": None if mullins is None else {"beta_fixed": mullins.beta}}


def _identifiability(stats: dict, cond: float) -> dict:
    """Identifiable: no correlated pair and κ(J, unit-norm columns) ≤ unc.COND_LIMIT."""
    return {"identifiable": bool(not stats["correlated_pairs"] and cond <= unc.COND_LIMIT),
            "condition_number": cond, "correlated_pairs": stats["correlated_pairs"], "warning": None}


def _with_figures(outcome, everything: RecordObjective, spec):
    """The outcome with its records (the objective over every data set) and their figures."""
    from vlab.identify.records.plots import record_figures

    records = [d for d in spec.datasets if d.kind in KINDS]
    outcome.extras["records"] = (everything, records)
    outcome.extras["figures"], outcome.extras["writers"] = record_figures(outcome, everything, records)
    return outcome
