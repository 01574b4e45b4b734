"""Bounded nonlinear least squares from many seeded starts.

Residual of point k of data set d (weight w_d, measured y, predicted ŷ(x), MPa):
    relative: r = √w_d (ŷ − y) / max(|y|, 0.01 max_d |y|)    (the floor keeps λ = 1, y = 0 finite;
              a data set of several outputs, torque and axial force, floors each by its own max)
    absolute: r = √w_d (ŷ − y)
minimised as ½ Σ r² by scipy.optimize.least_squares ("trf", box bounds on the internal
coordinates x, x_scale from the Jacobian), with the exact complex-step Jacobian of r. Starts are
drawn by each law's sampler from a numpy Generator seeded with ``seed``, around a modulus scale
estimated from the data (the median of y / ŷ_NH(μ = 1) over the fitted points).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from vlab.identify.jacobian import value_and_jacobian
from vlab.identify.kinds import FIT_KINDS
from vlab.identify.kinds.base import floor_of
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, incompressible_rows, response

__all__ = ["Objective", "StartResult", "multi_start", "predict"]

NEAR_BEST = 1e-2      # starts within 1 % of the best objective are "near the best"
AT_BEST = 1e-6        # ... within 1e-6 have "reached" it


def predict(model: Constitutive, X, d):
    """ŷ of data set d at internal coordinates X (m, n_x), MPa (a kind of vlab.identify.kinds:
    its own units, e.g. torque in N·mm)."""
    if d.kind in FIT_KINDS:
        return FIT_KINDS[d.kind].predict(model, X, d)
    return response(model, X, d.kind, d.a, d.b, d.measure)


class Objective:
    """The weighted residual vector r(x) of a list of homogeneous data sets and its Jacobian."""

    def __init__(self, model: Constitutive, datasets, residual: str = "relative"):
        self.model, self.datasets = model, list(datasets)
        self.y = np.concatenate([d.y for d in self.datasets])
        scales, weights = [], []
        for d in self.datasets:
            s = np.maximum(np.abs(d.y), floor_of(d)) if residual == "relative" else np.ones_like(d.y)
            scales.append(np.where(s > 0, s, 1.0))
            weights.append(np.full(len(d.y), np.sqrt(d.weight)))
        self.factor = np.concatenate(weights) / np.concatenate(scales)
        self._cache = (None, None, None)
        self.rows = None
        if model.bulk == "incompressible" and not any(d.kind in FIT_KINDS for d in self.datasets):
            # one law evaluation for every point of every set
            rows = [incompressible_rows(d.kind, d.a, d.b, d.measure) for d in self.datasets]
            self.rows = [np.concatenate([r[i] for r in rows])[None, :] for i in range(4)]
            self.rows[3] = self.rows[3] * self.factor

    def __call__(self, X):
        if self.rows is not None:
            c, _ = self.model.split(np.asarray(X)[:, None, :])
            w = self.model.law.w(c, *self.rows[:3])
            return (w[0] - w[2]) * self.rows[3] - self.y * self.factor
        pred = np.concatenate([predict(self.model, X, d) for d in self.datasets], axis=-1)
        return (pred - self.y) * self.factor

    def residual(self, x):
        """r at real x (one real evaluation; non-finite entries, e.g. past Gent's limit, → 1e10)."""
        with np.errstate(all="ignore"):
            r = np.real(self(np.asarray(x, float)[None, :])[0])
        return np.where(np.isfinite(r), r, 1e10)

    def jacobian(self, x):
        """∂r/∂x at real x by the complex step (exact)."""
        with np.errstate(all="ignore"):
            _, Jr = value_and_jacobian(self, x)
        return np.where(np.isfinite(Jr), Jr, 0.0)

    def evaluate(self, x):
        """(r, ∂r/∂x) at real x."""
        return self.residual(x), self.jacobian(x)


@dataclass(frozen=True)
class StartResult:
    x0: np.ndarray
    x: np.ndarray
    cost: float
    status: int
    message: str
    nfev: int
    at_bound: tuple = ()  # per x entry: the solution sits on a bound


def modulus_scale(datasets) -> float:
    """A shear-modulus estimate (MPa): median of y / ŷ of an incompressible Neo-Hookean, μ = 1."""
    nh = Constitutive(law_for("neo-hookean"))
    ratios = []
    for d in (d for d in datasets if d.kind != "volumetric" and not _needs_k(d)):
        base = np.real(predict(nh, np.ones((1, 1)), d)[0])
        ok = np.abs(base) > 1e-3
        ratios.extend((d.y[ok] / base[ok]).tolist())
    ratios = [r for r in ratios if r > 0]
    return float(np.median(ratios)) if ratios else 1.0


def _needs_k(d) -> bool:
    return d.kind in FIT_KINDS and FIT_KINDS[d.kind].compressible


def max_I1(datasets) -> float:
    """The largest I1 = Σ λ_i² the fitted data reach (incompressible states)."""
    out = 3.0
    for d in (d for d in datasets if d.kind != "volumetric"):
        if d.kind in FIT_KINDS:
            out = max(out, FIT_KINDS[d.kind].max_I1(d))
            continue
        if d.kind == "simple-shear":
            i1 = 3.0 + d.a ** 2
        else:
            lam = {"uniaxial": (d.a, d.a ** -0.5, d.a ** -0.5), "equibiaxial": (d.a, d.a, d.a ** -2),
                   "planar": (d.a, 1.0, 1.0 / d.a)}.get(d.kind)
            lam = lam or (d.a, d.b, 1.0 / (d.a * d.b))
            i1 = sum(np.asarray(v, float) ** 2 for v in lam)
        out = max(out, float(np.max(i1)))
    return out


def _bulk_start(rng, model: Constitutive, scale: float):
    if model.bulk != "fit":
        return [], [], []
    return [scale * float(np.exp(rng.uniform(np.log(30), np.log(3000))))], [1e-9], [np.inf]


def one_start(objective: Objective, x0, lo, hi, max_nfev: int = 400) -> StartResult:
    with np.errstate(invalid="ignore"):
        inside_lo = np.where(np.isfinite(lo), lo + 1e-9 * np.maximum(1.0, np.abs(lo)), -np.inf)
        inside_hi = np.where(np.isfinite(hi), hi - 1e-9 * np.maximum(1.0, np.abs(hi)), np.inf)
    x0 = np.clip(x0, inside_lo, inside_hi)
    sol = least_squares(objective.residual, x0, jac=objective.jacobian,
                        bounds=(lo, hi), method="trf", x_scale="jac", max_nfev=max_nfev,
                        ftol=1e-12, xtol=1e-12, gtol=1e-12)
    order = objective.model.law.canonical_order(sol.x)
    return StartResult(x0, sol.x[order], float(sol.cost), int(sol.status), str(sol.message), int(sol.nfev),
                       tuple(bool(a) for a in (sol.active_mask != 0)[order]))


def multi_start(objective: Objective, starts: int, seed: int, fit_sets, max_nfev: int = 400) -> tuple[list[StartResult], tuple]:
    """All starts (sorted by cost) and the bounds of the best, from Generator(seed)."""
    rng = np.random.default_rng(seed)
    scale, i1 = modulus_scale(fit_sets), max_I1(fit_sets)
    model = objective.model
    results, boxes = [], []
    for _ in range(starts):
        x0, lo, hi = model.law.start(rng, scale, i1)
        k0, klo, khi = _bulk_start(rng, model, scale)
        box = (np.r_[lo, klo], np.r_[hi, khi])
        results.append(one_start(objective, np.r_[x0, k0], *box, max_nfev))
        boxes.append(box)
    order = np.argsort([r.cost for r in results])
    return [results[i] for i in order], boxes[order[0]]


def summarize_starts(results: list[StartResult], model: Constitutive) -> dict:
    """How many starts reached the best objective, and how the others and near-best ones spread."""
    best = results[0]
    costs = np.array([r.cost for r in results])
    rel = (costs - best.cost) / max(best.cost, 1e-300)
    at_best = int(np.sum(rel <= AT_BEST))
    near = [r for r, q in zip(results, rel) if q <= NEAR_BEST]
    cb = model.card_vector(best.x)
    spread = max((float(np.max(np.abs(model.card_vector(r.x) - cb) / np.maximum(np.abs(cb), 1e-12)))
                  for r in near), default=0.0)
    others = rel[rel > AT_BEST]
    return {
        "count": len(results), "reached_best": at_best, "within_1_percent": len(near),
        "near_best_parameter_spread": spread,
        # agreement: a second start confirms the best and the near-best ones share its parameters
        "agree": bool(spread <= 1e-3 and (len(results) == 1 or at_best >= 2)),
        "others_objective_ratio": ({"min": float(1 + others.min()), "median": float(1 + np.median(others)),
                                    "max": float(1 + others.max())} if len(others) else None),
        "best_objective": float(best.cost), "evaluations": int(sum(r.nfev for r in results)),
    }


def timed_multi_start(objective, starts, seed, fit_sets, max_nfev: int = 400):
    t0 = time.perf_counter()
    results, box = multi_start(objective, starts, seed, fit_sets, max_nfev)
    return results, box, time.perf_counter() - t0
