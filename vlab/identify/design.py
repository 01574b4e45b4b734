"""Test design from the Fisher information of a card's constants: ``vlab design``.

A homogeneous test t (kind, stretch range, n points) measured with residual scatter s (relative
or MPa, the fit's residual convention) gives the Fisher information of the card values c

    F_t = J_tᵀ J_t / s²,   J_t = ∂r/∂c = f · ∂ŷ/∂x · T⁻¹        (n × p, exact by the complex step)

with f the residual's factor (1/max(|ŷ|, 0.01 max|ŷ|) for relative residuals, 1 for absolute
ones) and c = T x. Independent tests add: F = Σ F_t. The predicted covariance is Cov = F⁻¹, the
standard errors SE_i = √Cov_ii and corr_ij = Cov_ij / (SE_i SE_j) — the same linearisation
``vlab fit`` reports after the fact (vlab.identify.uncertainty), here before the data exist.

Determinacy: J with unit-norm columns has singular values σ_1 ≥ … ≥ σ_p; a direction v with
σ_k < σ_1 / κ_max (κ_max = 1e6, the limit vlab fit calls "not identifiable") changes no
prediction beyond the noise. A parameter with a component |v_i| > 0.01 along such a direction is
not determined by the combination: its standard error is null, with the direction as the reason.

Optimality values, in relative terms so that constants of any unit compare (Cov_rel = Cov_ij /
(|c_i| |c_j|), a zero constant scaled by 1):

    D = det(Cov_rel)^(1/(2p))     geometric-mean relative standard error (D-optimal: smallest,
                                  i.e. the largest det F)
    A = √(tr(Cov_rel) / p)        rms relative standard error (A-optimal: smallest)

both null when a parameter is not determined. A combination's ``verdict`` is "not determined",
"ill-conditioned" (some |corr| > 0.99 or a relative SE > 1: the constants are not resolved at this
noise — Ogden's uniaxial-only fits) or "well-posed".
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import numpy as np

from vlab.identify.datasets import Dataset
from vlab.identify.jacobian import value_and_jacobian
from vlab.identify.solve import Objective, max_I1, predict
from vlab.identify.uncertainty import COND_LIMIT, CORR_LIMIT, correlation

__all__ = ["PlannedTest", "CANDIDATE_KINDS", "default_range", "plan_rows", "assess", "combine", "combinations",
           "range_options", "add_each", "next_tests"]

CANDIDATE_KINDS = ("uniaxial", "equibiaxial", "planar", "simple-shear")
NULL_COMPONENT = 0.01


@dataclass(frozen=True)
class PlannedTest:
    """One candidate test: a kind over [lo, hi] (stretch, or shear γ for simple shear), n points."""

    kind: str
    lo: float
    hi: float
    points: int = 20

    @property
    def label(self) -> str:
        what = "shear" if self.kind == "simple-shear" else "stretch"
        return f"{self.kind} {what} {self.lo:.3g}..{self.hi:.3g}"

    def record(self) -> dict:
        return {"kind": self.kind, "range": [self.lo, self.hi], "points": self.points}


_LEVEL = {"uniaxial": lambda l: l * l + 2 / l, "equibiaxial": lambda l: 2 * l * l + l ** -4,
          "planar": lambda l: l * l + 1 + l ** -2, "simple-shear": lambda g: 3 + g * g}


def default_range(kind: str, fit_sets) -> tuple[float, float]:
    """The fitted range of ``kind`` if the data have it, else from 1.05 (γ 0.05) to the stretch
    that reaches the data's largest I1 (the same deformation level)."""
    fitted = [d for d in fit_sets if d.kind == kind]
    if fitted:
        return min(float(np.min(d.a)) for d in fitted), max(float(np.max(d.a)) for d in fitted)
    lo = 0.05 if kind == "simple-shear" else 1.05
    i1 = max(max_I1(fit_sets), _LEVEL[kind](lo * 1.5 if kind == "simple-shear" else 1.2))
    grid = np.linspace(lo, 12.0, 12000)
    reach = _LEVEL[kind](grid) >= i1
    return lo, float(grid[np.argmax(reach)]) if np.any(reach) else 12.0


def plan_rows(model, x, plan: PlannedTest, relative: bool) -> np.ndarray:
    """J_t = ∂r/∂c of one test at the card's internal coordinates x (n × p, per unit scatter)."""
    a = np.linspace(plan.lo, plan.hi, plan.points)
    d = Dataset(plan.kind, "", plan.kind, "fit", 1.0, "nominal", a, None, np.zeros_like(a))
    with np.errstate(all="ignore"):
        y, g = value_and_jacobian(lambda X: predict(model, X, d), x)
    f = 1.0 / np.maximum(np.abs(y), 0.01 * np.max(np.abs(y))) if relative else np.ones_like(y)
    return (g * f[:, None]) @ np.linalg.inv(model.transform)


def data_rows(model, x, fit_sets, residual: str) -> np.ndarray:
    """∂r/∂c of the fit file's own data sets (their weights and residual scaling)."""
    return Objective(model, fit_sets, residual).jacobian(x) @ np.linalg.inv(model.transform)


def _null_directions(J: np.ndarray):
    """(condition number of the column-scaled J, its near-null directions in physical units)."""
    norms = np.linalg.norm(J, axis=0)
    dead = norms == 0
    _, sv, vt = np.linalg.svd(J / np.where(dead, 1.0, norms), full_matrices=True)
    sv = np.r_[sv, np.zeros(J.shape[1] - len(sv))]
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    null = [v for s, v in zip(sv, vt) if s <= sv[0] / COND_LIMIT]
    null += [np.eye(J.shape[1])[i] for i in np.nonzero(dead)[0]]
    return cond, null, np.where(dead, 1.0, norms)


def _direction_text(v, norms, names) -> str:
    phys = v / norms
    phys = phys / phys[np.argmax(np.abs(phys))]
    terms = [f"{c:+.3g}·δ{n}" for c, n, s in zip(phys, names, v) if abs(s) > NULL_COMPONENT]
    return " ".join(terms)


def assess(J: np.ndarray, s: float, values, names) -> dict:
    """Predicted standard errors, correlations, D, A and the verdict of rows J at scatter s."""
    names, values = list(names), np.asarray(values, float)
    cond, null, norms = _null_directions(J)
    undetermined = sorted({i for v in null for i in np.nonzero(np.abs(v) > NULL_COMPONENT)[0]})
    Jn = J / norms  # unit columns: the pseudo-inverse truncates by conditioning, not by units
    cov = s * s * np.linalg.pinv(Jn.T @ Jn, rcond=1e-15, hermitian=True) / np.outer(norms, norms)
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    corr = correlation(cov)
    scale = np.where(values != 0, np.abs(values), 1.0)
    rel_cov = cov / np.outer(scale, scale)
    ok = not undetermined
    p = len(names)
    D = float(np.exp(np.linalg.slogdet(rel_cov)[1] / (2 * p))) if ok else None
    A = float(np.sqrt(np.trace(rel_cov) / p)) if ok else None
    off = np.abs(corr - np.diag(np.diag(corr)))
    det = [i for i in range(p) if i not in undetermined]
    worst = float(np.max(off[np.ix_(det, det)])) if len(det) > 1 else 0.0
    rel = {n: float(se[i] / scale[i]) for i, n in enumerate(names) if i not in undetermined}
    if not ok:
        verdict = "not determined"
        reason = (f"{', '.join(names[i] for i in undetermined)} not determined: the change "
                  + "; ".join(_direction_text(v, norms, names) for v in null)
                  + f" leaves every prediction unchanged (condition number of the scaled sensitivities "
                  f"{cond:.3g} > {COND_LIMIT:.0e})")
    elif worst > CORR_LIMIT or max(rel.values()) > 1.0:
        verdict = "ill-conditioned"
        reason = (f"worst |correlation| {worst:.4f}, largest relative standard error "
                  f"{100 * max(rel.values()):.3g} % ({max(rel, key=rel.get)}): not resolved at this noise")
    else:
        verdict, reason = "well-posed", None
    return {"standard_errors": {n: (None if i in undetermined else float(se[i])) for i, n in enumerate(names)},
            "relative_errors": {n: rel.get(n) for n in names},
            "correlation": {"order": names, "matrix": [[None if (i in undetermined or j in undetermined)
                                                        else round(float(corr[i, j]), 6) for j in range(p)]
                                                       for i in range(p)]},
            "D": D, "A": A, "condition_number": cond, "worst_correlation": worst,
            "verdict": verdict, "reason": reason}


def _rank_key(entry: dict):
    und = sum(v is None for v in entry["standard_errors"].values())
    return (und, entry["D"] if entry["D"] is not None else np.inf, entry["A"] or np.inf, len(entry["tests"]))


def combine(tests, s: float, values, names, max_size: int) -> list[dict]:
    """Every combination of 1..max_size of ``tests`` — (test, J_t) pairs, the test with ``label``
    and ``record()`` (a PlannedTest, or an FE specimen test: vlab.identify.fe_design) — best first
    (determined, then D, then A). Independent tests add: F = Σ J_tᵀ J_t / s²."""
    out = []
    for k in range(1, min(max_size, len(tests)) + 1):
        for combo in itertools.combinations(tests, k):
            J = np.vstack([rows for _, rows in combo])
            out.append({"tests": [t.record() for t, _ in combo], "label": " + ".join(t.label for t, _ in combo),
                        **assess(J, s, values, names)})
    return sorted(out, key=_rank_key)


def combinations(model, x, plans, s: float, relative: bool, max_size: int) -> list[dict]:
    """Every combination of 1..max_size candidate homogeneous tests, best first."""
    tests = [(p, plan_rows(model, x, p, relative)) for p in plans]
    return combine(tests, s, model.card_vector(x), list(model.names), max_size)


def range_options(plan: PlannedTest, steps: int = 4) -> list[PlannedTest]:
    """The plan and shorter ones: the same start, the top at 1/steps, 2/steps, … of the range."""
    tops = plan.lo + (plan.hi - plan.lo) * np.arange(1, steps + 1) / steps
    return [dataclasses.replace(plan, hi=float(t)) for t in tops]


def add_each(J0: np.ndarray, options, s: float, values, names) -> tuple[dict, list[dict]]:
    """(the present data's assessment, each option — a (test, J_t) pair — added to it, best first)
    with the expected reduction 1 − SE_new/SE_now of every standard error (null where either is null)."""
    names = list(names)
    now = assess(J0, s, values, names)
    out = []
    for test, rows in options:
        new = assess(np.vstack([J0, rows]), s, values, names)
        red = {n: (None if now["standard_errors"][n] in (None, 0.0) or new["standard_errors"][n] is None
                   else float(1.0 - new["standard_errors"][n] / now["standard_errors"][n])) for n in names}
        newly = [n for n in names if now["standard_errors"][n] is None and new["standard_errors"][n] is not None]
        out.append({"tests": [test.record()], "label": test.label, "reduction": red, "now_determined": newly,
                    **new})
    return now, sorted(out, key=_rank_key)


def next_tests(model, x, J0: np.ndarray, plans, s: float, relative: bool) -> tuple[dict, list[dict]]:
    """Each candidate homogeneous test, at four ranges, added to the present data (rows J0)."""
    options = [(q, plan_rows(model, x, q, relative)) for p in plans for q in range_options(p)]
    return add_each(J0, options, s, model.card_vector(x), model.names)
