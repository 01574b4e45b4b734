"""A validated fit file → the fit: parameters, uncertainty, per-data-set errors, information
criteria, multi-start agreement, identifiability, Drucker stability and the card.

Information criteria on the n weighted residuals with p parameters and SSR = Σ r²:
AIC = n ln(SSR/n) + 2p, BIC = n ln(SSR/n) + p ln n.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from vlab.identify import uncertainty as unc
from vlab.identify.card import card_of
from vlab.identify.drucker import kind_stability, states_stability
from vlab.identify.fitfile import FitSpec
from vlab.identify.jacobian import value_and_jacobian
from vlab.identify.kinds import FIT_KINDS
from vlab.identify.kinds.base import floor_of
from vlab.identify.solve import Objective, max_I1, predict, summarize_starts, timed_multi_start

__all__ = ["FitOutcome", "fit_homogeneous", "fit_any", "fit_one", "curves"]


@dataclass
class FitOutcome:
    """fit.json's dict (``data``) and what the report draws (best x, covariance)."""

    data: dict
    spec: FitSpec
    x: np.ndarray
    cov_x: np.ndarray
    tq: float
    extras: dict = field(default_factory=dict)

    @property
    def converged(self) -> bool:
        return bool(self.data["converged"])


def _dataset_errors(model, x, d) -> dict:
    pred = np.real(predict(model, x[None, :], d)[0])
    floor = floor_of(d)
    rel = (pred - d.y) / np.maximum(np.abs(d.y), np.where(floor > 0, floor, 1.0))
    lo, hi = float(np.min(d.a)), float(np.max(d.a))
    return {"name": d.name, "file": d.file, "kind": d.kind, "role": d.role, "weight": d.weight,
            "stress_measure": d.measure, "points": d.points, "range": [lo, hi],
            "rms_relative": float(np.sqrt(np.mean(rel ** 2))), "max_relative": float(np.max(np.abs(rel))),
            "rms_absolute_MPa": float(np.sqrt(np.mean((pred - d.y) ** 2)))} | _cleanup(d) | _geometry(d)


def _geometry(d) -> dict:
    """A closed-form kind's geometry (mm) and outputs (vlab.identify.kinds), as fit.json states them."""
    extra = d.extra or {}
    return {k: extra[k] for k in ("geometry", "outputs") if k in extra and d.kind in FIT_KINDS}


def _cleanup(d) -> dict:
    """A raw export's clean-up record (vlab.identify.records.raw), without the raw arrays."""
    rec = (d.extra or {}).get("cleanup")
    return {"cleanup": {k: v for k, v in rec.items() if k != "raw"}} if rec else {}


def _information(r: np.ndarray, p: int, s2: float, dof: int) -> dict:
    n = len(r)
    ssr = float(r @ r)
    ll = n * np.log(max(ssr, 1e-300) / n)
    return {"points": n, "parameters": p, "degrees_of_freedom": dof, "sum_of_squares": ssr,
            "residual_variance": s2, "AIC": float(ll + 2 * p), "BIC": float(ll + p * np.log(n))}


def _parameters(model, values) -> dict:
    law = model.law
    n = len(law.names)
    out = {k: v for k, v in law.card(values[:n]).items() if k != "model"}
    if model.bulk == "fit":
        out["K"] = float(values[n])
    return out


def _stability(model, x, spec) -> dict:
    kinds = {"uniaxial": None, "equibiaxial": None, "planar": None}
    for d in spec.datasets:
        if d.kind in ("uniaxial", "equibiaxial", "planar", "simple-shear"):
            lo, hi = kinds.get(d.kind) or (np.inf, -np.inf)
            kinds[d.kind] = (min(lo, float(np.min(d.a))), max(hi, float(np.max(d.a))))
    out = {k: kind_stability(model, x, k, r) for k, r in kinds.items()}
    fitted = [v["stable_over_fitted_range"] for v in out.values() if "stable_over_fitted_range" in v]
    states = {f"{d.name} ({d.kind})": states_stability(model, x, FIT_KINDS[d.kind].states(d))
              for d in spec.datasets if d.kind in FIT_KINDS and FIT_KINDS[d.kind].states is not None}
    fitted += [v["stable"] for v in states.values()]
    return {"kinds": out, "data_states": states, "stable_over_all_fitted_ranges": bool(all(fitted))}


def _candidates(model, x, fit_sets, factor_of):
    """Data sets that could separate correlated parameters: each standard kind to the fitted
    deformation level (the same largest I1) and every fitted kind to 1.5× its largest stretch."""
    from vlab.identify.datasets import Dataset
    i1 = max_I1(fit_sets)
    level = {"uniaxial": lambda l: l * l + 2 / l, "equibiaxial": lambda l: 2 * l * l + l ** -4,
             "planar": lambda l: l * l + 1 + l ** -2, "simple-shear": lambda g: 3 + g * g}
    out = []
    for kind, f in level.items():
        grid = np.linspace(1.0 if kind != "simple-shear" else 0.0, 12.0, 4000)
        top = float(grid[np.argmax(f(grid) >= i1)]) if np.any(f(grid) >= i1) else 12.0
        fitted = [float(np.max(d.a)) for d in fit_sets if d.kind == kind]
        tops = [(" (1.5 × the fitted range)", 1.5 * max(fitted))] if fitted else [("", top)]
        for tag, t in tops:
            a = np.linspace(0.05 if kind == "simple-shear" else 1.05, t, 20)
            d = Dataset(kind, "", kind, "fit", 1.0, "nominal", a, None, np.zeros_like(a))
            yhat, g = value_and_jacobian(lambda X: predict(model, X, d), x)
            rows = g * factor_of(yhat)[:, None]
            name = "shear" if kind == "simple-shear" else "stretch"
            out.append((f"{kind} data to {name} {t:.3g}{tag}", rows))
    return out


def _not_determined(model, J, dof: int, best) -> dict[str, str]:
    """{card parameter: why it gets no standard error}: no degrees of freedom, a direction the
    data do not determine (rank of the scaled Jacobian in card coordinates), or a parameter on
    a bound of the admissible box (the interval of an interior optimum does not apply)."""
    names = list(model.names)
    out = unc.undetermined(J @ np.linalg.inv(model.transform), names, dof)
    for n, b in zip(names, best.at_bound):
        if b and n not in out:
            out[n] = "on a bound of the admissible box: the interval of an interior optimum does not apply"
    return out


def _identifiability(model, x, J, cov_x, s2, cond, pairs, fit_sets, relative: bool, reasons=None) -> dict:
    loose = {k: v[v.index("not identifiable: ") + 18:] for k, v in (reasons or {}).items() if "not identifiable: " in v}
    ok = not pairs and not loose and cond <= unc.COND_LIMIT
    out = {"identifiable": bool(ok), "condition_number": cond if np.isfinite(cond) else None,
           "correlated_pairs": pairs, "not_determined": reasons or {}, "warning": None}
    if ok or len(x) < 2 or len(J) == 0:
        return out
    factor = (lambda y: 1.0 / np.maximum(np.abs(y), 1e-3 * np.max(np.abs(y)))) if relative else \
        (lambda y: np.ones_like(y))
    T = model.transform
    ranked = unc.separating_data(J @ np.linalg.pinv(T), T @ cov_x @ T.T, s2,
                                 [(lab, rows @ np.linalg.pinv(T)) for lab, rows in
                                  _candidates(model, x, fit_sets, factor)])
    out["separating_data"] = ranked[:5]
    top = sorted(pairs, key=lambda q: -abs(q[2]))
    what = ", ".join(f"|corr({a}, {b})| = {abs(c):.4f}" for a, b, c in top[:3]) or "no single pair"
    if len(top) > 3:
        what += f" and {len(top) - 3} more pairs"
    if loose:
        what = next(iter(loose.values())) + ("; " + what if top else "")
    best = ranked[0]
    if best["worst_correlation"] < unc.CORR_LIMIT:
        cure = (f"adding {best['data']} (20 points, same scatter) would bring the worst |correlation| to "
                f"{best['worst_correlation']:.3f}")
    else:
        cure = (f"none of the data sets tried separates them (best: {best['data']}, worst |correlation| "
                f"{best['worst_correlation']:.4f}): the model has more parameters than these modes determine")
    what += f"; condition number of the scaled Jacobian {cond:.3g}" if np.isfinite(cond) else ""
    out["warning"] = f"parameters not identifiable from the data given ({what}): {cure}"
    if best["worst_correlation"] >= 1.0:  # no candidate determines every direction
        out["warning"] = (f"parameters not identifiable from the data given ({what}): none of the data sets "
                          "tried determines every direction (a mode at the fitted deformation level, or "
                          "each fitted kind to 1.5 × its range): the model has more parameters than "
                          "these modes determine; fit a model with fewer parameters")
    return out


def fit_homogeneous(spec: FitSpec) -> FitOutcome:
    """Fit the homogeneous data sets of spec with multi-start least squares; everything else follows."""
    t0 = time.perf_counter()
    model = spec.model
    fit_sets = [d for d in spec.datasets if d.role == "fit" and d.kind != "specimen"]
    obj = Objective(model, fit_sets, spec.residual)
    results, box, t_fit = timed_multi_start(obj, spec.starts, spec.seed, fit_sets, spec.max_evaluations)
    best = results[0]
    x = best.x
    r, J = obj.evaluate(x)
    t1 = time.perf_counter()
    cov_x, s2, dof, cond = unc.covariance(J, r)
    values = model.card_vector(x)
    cov_c = model.transform @ cov_x @ model.transform.T
    reasons = _not_determined(model, J, dof, best)
    stats = unc.summarize(values, cov_c, list(model.names), dof, spec.confidence, reasons)
    ident = _identifiability(model, x, J, cov_x, s2, cond, stats["correlated_pairs"], fit_sets,
                             spec.residual == "relative", reasons)
    t2 = time.perf_counter()
    stability = _stability(model, x, spec)
    t3 = time.perf_counter()
    mu0 = model.law.mu0(values[:len(model.law.names)])
    converged, reason = _verdict(best, mu0, spec.max_evaluations)
    starts = summarize_starts(results, model)
    data = {
        "name": spec.name, "converged": bool(converged), "reason": reason,
        "model": _model_record(model, mu0),
        "parameters": _parameters(model, values), "uncertainty": stats["uncertainty"],
        "confidence": spec.confidence, "correlation": stats["correlation"],
        "datasets": [_dataset_errors(model, x, d) for d in spec.datasets if d.kind != "specimen"],
        "information": _information(r, len(x), s2, dof), "starts": starts, "identifiability": ident,
        "stability": stability, "card": card_of(model, values),
        "warnings": _warnings(model, best, ident, starts, stability, stats["uncertainty"]),
        "options": {"residual": spec.residual, "starts": spec.starts, "seed": spec.seed},
        "timing": {"fit_s": t_fit, "uncertainty_s": t2 - t1, "stability_s": t3 - t2,
                   "total_s": time.perf_counter() - t0},
    }
    data["trust"] = trust_of(data)
    return FitOutcome(data, spec, x, cov_x, stats["t_quantile"])


def trust_of(d: dict) -> dict:
    """Whether a converged card can be used as it is: every constant has an interval (none left
    undetermined by the data, none on a bound of the admissible box) and the card is Drucker-
    stable over the fitted ranges. `vlab fit` exits 3 (vlab.cli_io.EXIT_UNTRUSTED) when not."""
    because = []
    loose = [k for k, u in d["uncertainty"].items() if u["interval"] is None]
    if loose:
        reasons = sorted({d["uncertainty"][k]["reason"] for k in loose})
        because.append(f"no interval for {', '.join(loose)} ({'; '.join(reasons)})")
    if not d["stability"]["stable_over_all_fitted_ranges"]:
        because.append("the card is not Drucker-stable over the fitted ranges")
    refused = _run_refuses(d["card"]["material"])
    if refused:
        because.append(f"vlab run would refuse the card: {refused}")
    return {"trustworthy": not because, "because": because}


def _run_refuses(material: dict) -> str | None:
    """The error `vlab run` gives on the card's [material] table, or None when it reads it."""
    from vlab.fields import SceneError
    from vlab.materials.card import parse_material

    try:
        parse_material(dict(material))
    except (SceneError, ValueError, OverflowError) as exc:
        return str(exc)
    return None


def _verdict(best, mu0: float, max_evaluations: int) -> tuple[bool, str]:
    """(converged, reason) of the best start: a start that ran out of evaluations, or an optimum
    whose μ0 ≤ 0 (an inadmissible card), is not a converged fit."""
    if mu0 <= 0:
        return False, f"the best fit has mu0 = {mu0:g} MPa <= 0 (inadmissible card)"
    if best.status == 0:
        return False, (f"no start converged within {max_evaluations} evaluations (options.max_evaluations); "
                       f"best objective {best.cost:.4g}")
    return bool(best.status > 0 and np.isfinite(best.cost)), best.message


def _model_record(model, mu0: float) -> dict:
    """fit.json's model entry; an incompressible fit states the stand-in K its card carries."""
    out = {"name": model.law.model, "terms": model.law.terms, "bulk": model.bulk, "K": model.K,
           "volumetric": model.volumetric, "mu0": mu0}
    if model.bulk == "incompressible":
        out |= {"K_over_mu": model.K_over_mu, "card_K": model.K_over_mu * mu0}
    return out


def _warnings(model, best, ident: dict, starts: dict, stability: dict, uncertainty: dict) -> list[str]:
    """What a reader must know before trusting the constants: identifiability, no degrees of
    freedom, disagreeing starts, parameters on a bound, and a card that is not stable over the data."""
    out = [ident["warning"]] if ident["warning"] else []
    dof = sorted({u["reason"] for u in uncertainty.values() if (u["reason"] or "").startswith("n − p")})
    out += [f"no standard errors or intervals: {r}" for r in dof]
    if not starts["agree"]:
        out.append(f"the starts disagree: {starts['reached_best']} of {starts['count']} reached the best "
                   f"objective and those within 1 % of it differ in their parameters by up to "
                   f"{100 * starts['near_best_parameter_spread']:.3g} %: the optimum is not well defined "
                   "by these data")
    bound = [n for n, b in zip(model.names, best.at_bound) if b]
    if bound:
        out.append(f"parameters on a bound of the admissible box: {', '.join(bound)} (no interval: the "
                   "interval of an interior optimum does not apply; the data pull the constant past its range)")
    if not stability["stable_over_all_fitted_ranges"]:
        out.append("the fitted model is not Drucker-stable over the whole fitted range (see stability)")
    return out


def curves(outcome: FitOutcome, d, n: int = 120) -> dict:
    """Prediction and delta-method band of data set d on a fine grid (biaxial: at its points); a
    kind of vlab.identify.kinds with several outputs (torque, axial force) gives ``blocks`` curves
    on the same grid, one after the other in y."""
    from vlab.identify.datasets import Dataset
    model = outcome.spec.model
    blocks = len(d.y) // len(d.a) if d.kind in FIT_KINDS else 1
    if d.kind == "biaxial":
        grid = d
    else:
        a = np.linspace(float(np.min(d.a)), float(np.max(d.a)), n)
        grid = Dataset(d.name, d.file, d.kind, d.role, 1.0, d.measure, a, None, np.zeros(blocks * n), d.extra)
    y, g = value_and_jacobian(lambda X: predict(model, X, grid), outcome.x)
    yd, _ = value_and_jacobian(lambda X: predict(model, X, d), outcome.x)
    return {"a": grid.a, "y": y, "band": unc.band(g, outcome.cov_x, outcome.tq), "at_data": yd, "blocks": blocks}


def fit_any(spec: FitSpec, execution=None) -> FitOutcome:
    """fit_one of spec; with data sets of two or more specimens (data.specimen) also one fit per
    specimen and the statistics between them in fit.json → specimens (vlab.identify.specimens)."""
    from vlab.identify.specimens import fit_specimens
    return fit_specimens(spec, fit_one, execution)


def fit_one(spec: FitSpec, execution=None) -> FitOutcome:
    """The homogeneous fit, or the FE-in-the-loop fit when a data set is a specimen's readings
    (its whole-test solves on Dask with ``execution``, vlab.study.sweep.Execution)."""
    if spec.fe is not None and any(d.kind == "field" for d in spec.datasets):
        from vlab.identify.field_fit import fit_field
        return fit_field(spec, execution)
    if spec.fe is not None:
        from vlab.identify.fe_loop import fit_specimen
        return fit_specimen(spec, execution)
    from vlab.identify.records.fit import has_records
    if has_records(spec):
        from vlab.identify.records.fit import fit_records
        return fit_records(spec)
    return fit_homogeneous(spec)
