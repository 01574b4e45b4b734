"""Uncertainty of a least-squares fit from its Jacobian at the optimum.

With n residuals r, p parameters, J = ∂r/∂x (n × p) and s² = Σ r² / (n − p) (the residual
variance, in the residual's units: relative or MPa; n counts the informative points, i.e. rows
of J that are not zero: a point at the reference state λ = 1 has ŷ = y = 0 for every x):
    Cov_x = s² D⁻¹ (Ĵᵀ Ĵ)⁻¹ D⁻¹   Ĵ = J D⁻¹, D = diag(‖J_:,i‖) (column scaling, then the SVD of Ĵ)
    Cov_c = T Cov_x Tᵀ            for the card values c = T x
    SE_i = √Cov_ii,  interval c_i ± t_{(1+q)/2, n−p} SE_i  (q the confidence, Student's t)
    corr_ij = Cov_ij / (SE_i SE_j)
A predicted curve ŷ(λ) gets the delta-method band ŷ ± t √(g Cov_x gᵀ), g = ∂ŷ/∂x (complex step).
Rank: a direction of the parameters is determined by the data when its singular value of Ĵ is
at least RANK_TOL times the largest. Where it is not (or n − p ≤ 0), the parameters with a
component along the undetermined directions get no standard error or interval (None, with the
reason): the pseudo-inverse would drop the direction and report an error that is too small.
Identifiability: the condition number of J with unit-norm columns (κ > 1e6 means JᵀJ is
near-singular) and every pair with |corr| > 0.99; the warning names the data set (kind and
stretch range) whose addition lowers the worst correlation most, computed by adding its
sensitivity rows to JᵀJ at the same residual scatter.
"""

from __future__ import annotations

import numpy as np
from scipy.special import stdtrit  # Student's t quantile (scipy.stats costs seconds to import)

__all__ = ["covariance", "summarize", "band", "separating_data", "undetermined", "informative_points"]

CORR_LIMIT = 0.99
COND_LIMIT = 1e6
RANK_TOL = 1e-10   # singular value of Ĵ, relative to the largest, below which a direction is not determined
NULL_TOL = 1e-6    # a parameter's component along an undetermined direction above which it is not determined


def informative_points(J: np.ndarray) -> int:
    """Rows of J that are not zero (a point at the reference state carries no information)."""
    norms = np.linalg.norm(J, axis=1)
    top = float(np.max(norms)) if len(norms) else 0.0
    return int(np.sum(norms > 1e-14 * top)) if top > 0 else 0


def _scaled_svd(J: np.ndarray):
    """(column norms D, the p singular values of Ĵ = J D⁻¹ (zeros past n), V) with Ĵ = U S Vᵀ."""
    n, p = J.shape
    norms = np.linalg.norm(J, axis=0)
    norms = np.where(norms > 0, norms, 1.0)
    if n == 0:
        return norms, np.zeros(p), np.eye(p)
    # V is p × p either way; the full U (n × n) is never used (a 24k-row field fit asked for 4.5 GB)
    _, s, Vt = np.linalg.svd(J / norms, full_matrices=n < p)
    sv = np.zeros(p)
    sv[:len(s)] = s[:p]
    return norms, sv, Vt.T


def _determined(sv: np.ndarray) -> np.ndarray:
    return sv > RANK_TOL * sv[0] if sv[0] > 0 else np.zeros(len(sv), bool)


def _inverse(J: np.ndarray) -> np.ndarray:
    """(JᵀJ)⁻¹ on the determined directions, through the SVD of the column-scaled J."""
    norms, sv, V = _scaled_svd(J)
    keep = _determined(sv)
    inner = (V[:, keep] / sv[keep] ** 2) @ V[:, keep].T
    return inner / np.outer(norms, norms)


def covariance(J: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, float, int, float]:
    """(Cov_x, s², degrees of freedom, condition number of the column-scaled J)."""
    p = J.shape[1]
    dof = informative_points(J) - p
    s2 = float(r @ r / dof) if dof > 0 else float("nan")
    _, sv, _ = _scaled_svd(J)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    return s2 * _inverse(J), s2, dof, cond


def _combination(w: np.ndarray, names) -> str:
    """"C10 + 0.667 C01": w scaled so its largest |coefficient| is 1 (and positive)."""
    w = w / w[np.argmax(np.abs(w))]
    out = ""
    for c, n in zip(w, names):
        if abs(c) < 1e-3:  # (a term below 0.1 % of the largest says nothing a reader can use)
            continue
        mag = "" if abs(abs(c) - 1) < 5e-4 else f"{abs(c):.3g} "
        out += (" − " if c < 0 else " + ") if out else ("−" if c < 0 else "")
        out += mag + n
    return out


def undetermined(Jc: np.ndarray, names, dof: int) -> dict[str, str]:
    """{card parameter: why its standard error is not determined} from the Jacobian in card
    coordinates: all of them when n − p ≤ 0, else those with a component along a direction
    whose singular value of the column-scaled Jc is below RANK_TOL of the largest; the reason
    names the combinations of them the data do determine."""
    names = list(names)
    n, p = informative_points(Jc), len(names)
    out = _rank_deficient(Jc, names)
    if dof <= 0:
        ref = Jc.shape[0] - n
        note = f"; {ref} of the {Jc.shape[0]} points are at the reference state and carry no information" if ref else ""
        base = f"n − p = {n} − {p} = {n - p}: no degrees of freedom left to estimate the scatter{note}"
        out = {k: base + (f"; {out[k]}" if k in out else "") for k in names}
    return out


def _rank_deficient(Jc: np.ndarray, names: list) -> dict[str, str]:
    p = len(names)
    norms, sv, V = _scaled_svd(Jc)
    keep = _determined(sv)
    null = V[:, ~keep]
    loose = [i for i in range(p) if np.linalg.norm(null[i]) > NULL_TOL]
    if not loose:
        return {}
    rows = (V[:, keep] * norms[:, None]).T[:, loose]   # determined combinations, on the loose ones
    s, vt = np.linalg.svd(rows, full_matrices=False)[1:] if rows.size else (np.zeros(0), None)
    basis = vt[s > 1e-8 * s[0]] if len(s) and s[0] > 0 else np.zeros((0, len(loose)))
    sub = [names[i] for i in loose]
    terms = [_combination(b, sub) for b in basis]
    if len(basis) == 0:
        what = None
    elif len(basis) <= 2 and all(t.count(" + ") + t.count(" − ") < 4 for t in terms):
        what = " and ".join(terms)
    else:
        what = f"{len(basis)} combinations of {', '.join(sub)}"
    reason = (f"not identifiable: the data determine only {what}" if what else
              f"not identifiable: the data determine none of {', '.join(sub)}") + f" (rank {int(keep.sum())} of {p})"
    return {names[i]: reason for i in loose}


def correlation(cov: np.ndarray) -> np.ndarray:
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(all="ignore"):
        out = cov / np.outer(se, se)
    return np.where(np.isfinite(out), out, 0.0)


def _entry(value, se, tq, reason):
    if reason is None and not (np.isfinite(se) and np.isfinite(tq)):
        reason = "not determined"
    if reason is None and se == 0:
        reason = "the residuals are all zero: no scatter to estimate an interval from"
    if reason is not None:
        return {"value": float(value), "standard_error": None, "interval": None, "relative_error": None,
                "reason": reason}
    return {"value": float(value), "standard_error": float(se),
            "interval": [float(value - tq * se), float(value + tq * se)],
            "relative_error": float(se / abs(value)) if value else None, "reason": None}


def summarize(values, cov_c, names, dof: int, confidence: float, reasons: dict | None = None) -> dict:
    """Standard errors, intervals and correlations of the card values (in ``names`` order);
    ``reasons`` {name: why}: parameters without a standard error (None, with the reason), left
    out of the correlations (None) and the correlated pairs."""
    reasons = reasons or {}
    se = np.sqrt(np.clip(np.diag(cov_c), 0, None))
    tq = float(stdtrit(dof, 0.5 + confidence / 2)) if dof > 0 else float("nan")
    unc = {n: _entry(v, s, tq, reasons.get(n)) for n, v, s in zip(names, values, se)}
    known = [unc[n]["standard_error"] is not None for n in names]
    corr = correlation(cov_c)
    pairs = [(names[i], names[j], float(corr[i, j])) for i in range(len(names))
             for j in range(i + 1, len(names)) if known[i] and known[j] and abs(corr[i, j]) > CORR_LIMIT]
    matrix = [[round(float(corr[i, j]), 6) if known[i] and known[j] else None for j in range(len(names))]
              for i in range(len(names))]
    return {"uncertainty": unc, "t_quantile": tq,
            "correlation": {"order": list(names), "matrix": matrix},
            "correlated_pairs": pairs}


def band(gradient: np.ndarray, cov_x: np.ndarray, tq: float) -> np.ndarray:
    """Delta-method half-width t √(g Cov gᵀ) of each predicted point (gradient (n, p))."""
    return tq * np.sqrt(np.clip(np.einsum("ij,jk,ik->i", gradient, cov_x, gradient), 0, None))


def separating_data(J, cov_x, s2, candidates) -> list[dict]:
    """Each candidate (label, J_c rows at the same residual scale) → the worst |corr| with it
    added (1 when a direction is still not determined), best first (the correlations do not
    depend on s², which is kept for the signature)."""
    out = []
    for label, Jc in candidates:
        stacked = np.vstack([J, Jc])
        _, sv, _ = _scaled_svd(stacked)
        if not _determined(sv).all():  # still a direction the data do not determine
            out.append({"data": label, "worst_correlation": 1.0})
            continue
        c = correlation(_inverse(stacked))
        worst = float(np.max(np.abs(c - np.diag(np.diag(c))))) if len(c) > 1 else 0.0
        out.append({"data": label, "worst_correlation": worst})
    return sorted(out, key=lambda d: d["worst_correlation"])
