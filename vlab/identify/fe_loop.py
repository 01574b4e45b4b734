"""FE in the loop: fit the scene's material constants until vlab's own test reproduces the
specimen's readings (extensometer strain e_i, load-cell force F_i in N).

The simulated force at a measured strain is the cubic spline F(e) through the recorded levels
(and (0, 0)); its sensitivity at fixed strain is S_k = dF_k/dp − F'(e_k) de_k/dp (the strain
itself moves with p between clamped grips), splined the same way. Residuals r_i = (F(e_i) − F_i)/s_i
(s_i = max(|F_i|, 0.01 max|F|) relative, 1 N absolute; the spline extends at most 10 % of the
strain range beyond the last level, since the end strain between clamped grips moves with p), J_i = S(e_i)/s_i. Levenberg–Marquardt:
(JᵀJ + λ diag JᵀJ) δ = −Jᵀr, a step that lowers Σ r² is kept (λ/10), else λ×10; every trial
point is one whole-test solve; a trial that would leave the admissible box (vlab.identify.fe_spec.
admissible) is halved first, a trial whose test fails is a rejected step. Converged when every
|δ_j| ≤ 0.01 standard errors (or 1e-8 p_j), i.e. the last step moved nothing the data can resolve,
or when the rms weighted residual is below MATCHED (noise-free readings reproduced). A cruciform's
two axes each have their own spline and residuals. Uncertainty as for homogeneous fits.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from scipy.interpolate import CubicSpline

from vlab.fields import SceneError
from vlab.identify import uncertainty as unc
from vlab.identify.card import card_of
from vlab.identify.drucker import kind_stability
from vlab.identify.fe_sensitivity import simulate
from vlab.identify.fe_spec import admissible
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive

__all__ = ["fit_specimen", "residuals", "closed_form", "lm_fit"]

EXTRAPOLATION = 0.1  # data may reach 10 % of the simulated strain range beyond its end
MATCHED = 1e-9  # rms weighted residual at which noise-free readings count as reproduced (solver rtol 1e-8)


def _axis(sim, a: int, e_data, F_data, weight: float, relative: bool, name: str):
    """(r, J, F(e_i)) of one loading axis: the spline of the simulated force at the data's strains."""
    e = np.r_[0.0, sim.strain[:, a]]
    F = np.r_[0.0, sim.force[:, a]]
    if np.any(np.diff(e) <= 0):
        raise RuntimeError(f"the simulated extensometer strain of axis {'xy'[a]} is not monotonic; "
                           "cannot match strains")
    lo, hi = min(e[0], e[-1]), max(e[0], e[-1])
    reach = EXTRAPOLATION * (hi - lo)  # the end strain moves with the constants between clamped grips
    if np.min(e_data) < lo - reach or np.max(e_data) > hi + reach:
        raise SceneError(f"{name}: the data's strain range {np.min(e_data):.4g}..{np.max(e_data):.4g} (axis "
                         f"{'xy'[a]}) is not covered by the scene's test ({lo:.4g}..{hi:.4g}): change the "
                         "scene's test.stretch")
    spline = CubicSpline(e, F)
    dF, de = sim.dforce[:, a, :], sim.dstrain[:, a, :]
    S = np.vstack([np.zeros(dF.shape[1]), dF - spline(sim.strain[:, a], 1)[:, None] * de])
    Fi = spline(e_data)
    Si = CubicSpline(e, S, axis=0)(e_data)
    scale = np.maximum(np.abs(F_data), 0.01 * np.max(np.abs(F_data))) if relative else np.ones_like(F_data)
    w = np.sqrt(weight) / scale
    return (Fi - F_data) * w, Si * w[:, None], Fi


def residuals(sim, d, relative: bool):
    """(r, J, F(e_i)) of data set d against a simulation: axis x, then (a cruciform's) axis y,
    each force relative to its own readings."""
    n = d.points
    parts = [_axis(sim, 0, d.a, d.y[:n], d.weight, relative, d.name)]
    if d.b is not None:
        parts.append(_axis(sim, 1, d.b, d.y[n:], d.weight, relative, d.name))
    return tuple(np.concatenate([q[k] for q in parts]) for k in range(3))


def _relative_error(Fi, y):
    return (Fi - y) / np.maximum(np.abs(y), 0.01 * np.max(np.abs(y)))


class _Problem:
    def __init__(self, spec, run=None):
        self.spec, self.fe, self.run = spec, spec.fe, run
        self.sets = [d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"]
        self.names = self.fe["parameters"]
        self.solves = 0   # evaluations of the whole test (solved, or read back from the cache)
        self.cached = 0
        self.counts: dict = {}  # factorizations and back-substitutions summed over the solves

    def values(self, p):
        return self.fe["fixed"] | dict(zip(self.names, map(float, p)))

    def evaluate(self, p):
        self.solves += 1
        sim = simulate(self.fe, self.values(p), run=self.run)
        self.cached += sim.cached
        for k, v in sim.counts.items():
            self.counts[k] = self.counts.get(k, 0) + v
        parts = [residuals(sim, d, self.spec.residual == "relative") for d in self.sets]
        return np.concatenate([q[0] for q in parts]), np.vstack([q[1] for q in parts]), sim


def _lm(prob: _Problem, p0):
    p, lam = np.asarray(p0, float), 1e-3
    r, J, sim = prob.evaluate(p)
    trail = [{"solve": 1, "parameters": p.tolist(), "objective": float(0.5 * r @ r), "accepted": True}]
    while prob.solves < prob.fe["max_solves"]:
        A, g = J.T @ J, J.T @ r
        delta = np.linalg.solve(A + lam * np.diag(np.diag(A)), -g)
        while not admissible(prob.names, p + delta, p):  # no solve spent on an inadmissible card
            delta *= 0.5
        try:
            r2, J2, sim2 = prob.evaluate(p + delta)
            ok, note = r2 @ r2 < r @ r, None
        except (RuntimeError, SceneError) as exc:  # no test at the trial constants (Gent chains lock, ...)
            ok, note = False, str(exc)
        trail.append({"solve": prob.solves, "parameters": (p + delta).tolist(),
                      "objective": float(0.5 * r2 @ r2) if note is None else None, "accepted": bool(ok)}
                     | ({"failed": note} if note else {}))
        if ok:
            cov, *_ = unc.covariance(J2, r2)
            se = np.sqrt(np.clip(np.diag(cov), 0, None))
            p, r, J, sim, lam = p + delta, r2, J2, sim2, lam / 10
            if np.all(np.abs(delta) <= np.maximum(0.01 * se, 1e-8 * np.abs(p))):
                return p, r, J, sim, trail, True, "the last step moved every constant by < 0.01 standard errors"
            if r @ r <= MATCHED ** 2 * len(r):
                return p, r, J, sim, trail, True, f"the readings are matched to {MATCHED:g} (relative rms)"
        else:
            lam *= 10
    return p, r, J, sim, trail, False, f"not converged within fe.max_solves = {prob.fe['max_solves']} whole-test solves"


_HOMOGENEOUS_KIND = {"uniaxial": "uniaxial", "planar": "planar", "biaxial": "biaxial"}


def _homogeneous_comparison(spec, sim, p, se, names) -> dict:
    """The closed-form fit of the same readings, as if the specimen were ideal: stress = F/A0,
    stretch = 1 + e, in the scene's kind (a cruciform: biaxial with both axes)."""
    from vlab.identify.datasets import Dataset
    from vlab.identify.fitting import fit_homogeneous

    bulk = "fit" if "K" in names else "fixed"
    model = closed_form(spec.fe, bulk)
    kind = _HOMOGENEOUS_KIND[spec.fe["scene"].test.kind]
    if kind == "biaxial" and 1 not in spec.fe["axes"]:
        return {"kind": None, "note": "one axis of a biaxial test has no closed form of its own: give both "
                                      "axes (strain2, force2) for the homogeneous comparison"}
    sets = []
    for d in (d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"):
        n, two = d.points, d.b is not None
        y = np.r_[d.y[:n] / sim.area0[0], d.y[n:] / sim.area0[1]] if two else d.y / sim.area0[0]
        sets.append(Dataset(d.name, d.file, kind, "fit", d.weight,
                            "nominal", 1.0 + d.a, None if not two else 1.0 + d.b, y))
    hom = fit_homogeneous(dataclasses.replace(spec, model=model, datasets=tuple(sets), fe=None, starts=3))
    values = spec.fe["fixed"] | dict(zip(model.names, model.card_vector(hom.x)))
    out = {"kind": sets[0].kind, "parameters": {n: float(values[n]) for n in names},
           "area0_mm2": sim.area0.tolist()}
    out["difference_in_standard_errors"] = {n: float((values[n] - v) / s) if s > 0 else None
                                            for n, v, s in zip(names, p, se)}
    out["relative_difference"] = {n: float(values[n] / v - 1) for n, v in zip(names, p)}
    return out


def closed_form(fe: dict, bulk: str) -> Constitutive:
    """The identification library's form of the scene's law (vlab's Neo-Hookean, or a card model
    with the scene's volumetric energy); bulk "fit" or "fixed" at the scene's K."""
    terms = sum(1 for n in fe["fixed"] if n.startswith("alpha[")) or 1
    return Constitutive(law_for(fe.get("model", "neo-hookean"), terms), bulk,
                        None if bulk == "fit" else fe["fixed"]["K"], fe.get("volumetric") or "quadratic")


def _card_space(model: Constitutive, values: dict, names, cov):
    """Internal coordinates x of the card (values) and the covariance of the fitted constants
    mapped to x (zero for the constants held fixed): card = T x, Cov_x = T⁻¹ Cov T⁻ᵀ."""
    order = list(model.names)
    card = np.array([values[n] for n in order])
    T_inv = np.linalg.inv(model.transform)
    cov_card = np.zeros((len(order), len(order)))
    idx = [order.index(n) for n in names]
    cov_card[np.ix_(idx, idx)] = cov
    return T_inv @ card, T_inv @ cov_card @ T_inv.T


def fit_specimen(spec, execution=None):
    """The FE-in-the-loop fit of spec's specimen data sets; ``execution`` (vlab.study.sweep.Execution)
    runs the whole-test solves on Dask (vlab.identify.fe_dask), None in this process."""
    t0 = time.perf_counter()
    if execution is None:
        return _fit_specimen(spec, None, t0)
    from vlab.identify.fe_dask import DaskSolves

    with DaskSolves(execution) as run:
        return _fit_specimen(spec, run, t0)


def _fit_specimen(spec, run, t0):
    from vlab.identify.fitting import FitOutcome, _information, trust_of

    prob = _Problem(spec, run)
    names = prob.names
    (p, r, J, sim, trail, converged, reason), (cov, s2, dof, cond, reasons, stats) = lm_fit(prob, spec)
    t_fit = time.perf_counter() - t0
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    values = prob.values(p)
    model = closed_form(spec.fe, "fit")
    x, cov_x = _card_space(model, values, names, cov)
    datasets = [_dataset_errors(sim, d) for d in spec.datasets if d.kind == "specimen"]
    data = {
        "name": spec.name, "converged": bool(converged), "reason": reason,
        "model": _model_entry(spec, model, values, names),
        "parameters": {n: float(v) for n, v in zip(names, p)}, "uncertainty": stats["uncertainty"],
        "confidence": spec.confidence, "correlation": stats["correlation"], "datasets": datasets,
        "information": _information(r, len(p), s2, dof),
        "starts": _one_start(), "identifiability": _identifiability(stats, reasons, cond),
        "stability": _specimen_stability(model, x, spec),
        "card": card_of(model, model.card_vector(x), None if "K" in names else "K held at the scene's value"),
        "fe": _fe_record(spec, prob, run, trail, _homogeneous_comparison(spec, sim, p, se, names)),
        "warnings": [f"vlab run: {w}" for w in sim.warnings],
        "options": {"residual": spec.residual},
        "timing": {"fit_s": t_fit, "total_s": time.perf_counter() - t0},
    }
    data["trust"] = trust_of(data)
    outcome = FitOutcome(data, dataclasses.replace(spec, model=model), x, cov_x, stats["t_quantile"])
    _attach_figure(outcome, lambda path: _plot(spec, sim, J, cov, stats["t_quantile"], path))
    return outcome


def lm_fit(prob, spec):
    """(_lm's result from fe.start, (cov, s², dof, κ, undetermined, summary) at its end point); a
    test that fails at the start is a SceneError."""
    names = list(prob.names)
    try:
        p, r, J, sim, trail, converged, reason = _lm(prob, np.array([spec.fe["start"][n] for n in names]))
    except RuntimeError as exc:
        raise SceneError(f"fe.scene: {exc}") from None
    cov, s2, dof, cond = unc.covariance(J, r)
    reasons = unc.undetermined(J, names, dof)
    stats = unc.summarize(p, cov, names, dof, spec.confidence, reasons)
    return (p, r, J, sim, trail, converged, reason), (cov, s2, dof, cond, reasons, stats)


def _model_entry(spec, model: Constitutive, values: dict, names) -> dict:
    """fit.json's model entry: the law, its terms, the bulk term (fitted or the scene's K), μ0."""
    return {"name": model.law.model, "terms": model.law.terms, "bulk": "fit" if "K" in names else "fixed",
            "K": values["K"], "volumetric": spec.fe.get("volumetric") or "vlab neo-hookean",
            "mu0": model.law.mu0([values[n] for n in model.law.names])}


def _one_start() -> dict:
    """fit.json's starts entry of an FE-in-the-loop fit (one start, from fe.start)."""
    return {"count": 1, "reached_best": 1, "agree": True, "others_objective_ratio": None,
            "note": "FE-in-the-loop fits start once, from fe.start"}


def _identifiability(stats: dict, reasons, cond: float) -> dict:
    """Identifiable: no correlated pair, no undetermined constant, κ(J, unit-norm columns) ≤ unc.COND_LIMIT."""
    return {"identifiable": not stats["correlated_pairs"] and not reasons and cond <= unc.COND_LIMIT,
            "condition_number": cond, "correlated_pairs": stats["correlated_pairs"], "not_determined": reasons}


def _attach_figure(outcome, writer) -> None:
    """The specimen figure the fit report draws beside the closed-form ones."""
    outcome.extras["writers"] = [("specimen.png", writer)]
    outcome.extras["figures"] = [("specimen.png", "The specimen's readings (points) against vlab's own test at the "
                                  "fitted constants (line), force against extensometer strain.")]


def _fe_record(spec, prob, run, trail, homogeneous: dict) -> dict:
    """fit.json's fe entry: the scene, its solves (and how many came from the cache), the
    instruments' axes, factorization counts, where the solves ran and the homogeneous comparison."""
    return {"scene": spec.fe["scene_path"], "solves": prob.solves, "from_cache": prob.cached,
            "axes": ["xy"[a] for a in spec.fe["axes"]], "counts": prob.counts,
            "execution": {"dask": False} if run is None else run.describe(),
            "cache": spec.fe.get("cache"), "trail": trail, "homogeneous_fit": homogeneous}


def _specimen_stability(model, x, spec) -> dict:
    """Drucker stability of the FE-fitted card along the homogeneous paths, judged over the data:
    one-axis readings span the uniaxial stretches 1 + strain; two-axis (cruciform) readings are
    judged on both the uniaxial and the equibiaxial path up to the largest arm strain (the centre
    of a cruciform lies between those paths, not on either: stated in ``basis``)."""
    ranges: dict = {}
    for d in (d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"):
        strain = np.concatenate([d.a, d.b]) if d.b is not None else np.asarray(d.a)
        span = (1.0 + min(0.0, float(np.min(strain))), 1.0 + float(np.max(strain)))
        for kind in ("uniaxial", "equibiaxial") if d.b is not None else ("uniaxial",):
            lo, hi = ranges.get(kind, span)
            ranges[kind] = (min(lo, span[0]), max(hi, span[1]))
    kinds = {k: kind_stability(model, x, k, ranges.get(k)) for k in ("uniaxial", "equibiaxial", "planar")}
    judged = [v["stable_over_fitted_range"] for v in kinds.values() if "stable_over_fitted_range" in v]
    basis = ("stretch = 1 + extensometer strain on the uniaxial path"
             + ("; two-axis readings also on the equibiaxial path" if "equibiaxial" in ranges else ""))
    return {"kinds": kinds, "stable_over_all_fitted_ranges": bool(all(judged)), "basis": basis}


def _dataset_errors(sim, d) -> dict:
    """fit.json's row of a specimen data set: its errors at the fitted constants (both axes)."""
    _, _, Fi = residuals(sim, d, True)
    n = d.points
    rel = np.concatenate([_relative_error(Fi[:n], d.y[:n])]
                         + ([_relative_error(Fi[n:], d.y[n:])] if d.b is not None else []))
    return {"name": d.name, "file": d.file, "kind": "specimen", "role": d.role, "points": d.points,
            "rms_relative": float(np.sqrt(np.mean(rel ** 2))), "max_relative": float(np.max(np.abs(rel))),
            "rms_absolute_N": float(np.sqrt(np.mean((Fi - d.y) ** 2)))}


def _plot(spec, sim, J, cov, tq, path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.2))
    for d in (d for d in spec.datasets if d.kind == "specimen"):
        n = d.points
        ax.plot(d.a, d.y[:n], "o", ms=4, label=f"{d.name} ({d.role}), axis x")
        if d.b is not None:
            ax.plot(d.b, d.y[n:], "s", ms=4, label=f"{d.name} ({d.role}), axis y")
    for a in range(sim.strain.shape[1]):
        ax.plot(np.r_[0, sim.strain[:, a]], np.r_[0, sim.force[:, a]], "k-" if a == 0 else "k--", lw=1.2,
                label=f"vlab test at the fitted constants, axis {'xy'[a]}")
    ax.set_xlabel("extensometer strain")
    ax.set_ylabel("force (N)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
