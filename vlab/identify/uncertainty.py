"""Uncertainty of a least-squares fit from its Jacobian at the optimum.

With n residuals r, p parameters, J = ∂r/∂x (n × p) and s² = Σ r² / (n − p) (the residual
variance, in the residual's units: relative or MPa):
    Cov_x = s² (JᵀJ)⁻¹            (pseudo-inverse through the SVD of J)
    Cov_c = T Cov_x Tᵀ            for the card values c = T x
    SE_i = √Cov_ii,  interval c_i ± t_{(1+q)/2, n−p} SE_i  (q the confidence, Student's t)
    corr_ij = Cov_ij / (SE_i SE_j)
A predicted curve ŷ(λ) gets the delta-method band ŷ ± t √(g Cov_x gᵀ), g = ∂ŷ/∂x (complex step).
Identifiability: the condition number of J with unit-norm columns (κ > 1e6 means JᵀJ is
near-singular) and every pair with |corr| > 0.99; the warning names the data set (kind and
stretch range) whose addition lowers the worst correlation most, computed by adding its
sensitivity rows to JᵀJ at the same residual scatter.
"""

from __future__ import annotations

import numpy as np
from scipy.special import stdtrit  # Student's t quantile (scipy.stats costs seconds to import)

__all__ = ["covariance", "summarize", "band", "separating_data"]

CORR_LIMIT = 0.99
COND_LIMIT = 1e6


def covariance(J: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, float, int, float]:
    """(Cov_x, s², degrees of freedom, condition number of the column-scaled J)."""
    n, p = J.shape
    dof = n - p
    s2 = float(r @ r / dof) if dof > 0 else float("nan")
    norms = np.linalg.norm(J, axis=0)
    norms = np.where(norms > 0, norms, 1.0)
    sv = np.linalg.svd(J / norms, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    cov = s2 * np.linalg.pinv(J.T @ J, rcond=1e-15, hermitian=True)
    return cov, s2, dof, cond


def correlation(cov: np.ndarray) -> np.ndarray:
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    with np.errstate(all="ignore"):
        out = cov / np.outer(se, se)
    return np.where(np.isfinite(out), out, 0.0)


def summarize(values, cov_c, names, dof: int, confidence: float) -> dict:
    """Standard errors, intervals and correlations of the card values (in ``names`` order)."""
    se = np.sqrt(np.clip(np.diag(cov_c), 0, None))
    tq = float(stdtrit(dof, 0.5 + confidence / 2)) if dof > 0 else float("nan")
    unc = {n: {"standard_error": float(s), "interval": [float(v - tq * s), float(v + tq * s)],
               "relative_error": float(s / abs(v)) if v else None}
           for n, v, s in zip(names, values, se)}
    corr = correlation(cov_c)
    pairs = [(names[i], names[j], float(corr[i, j])) for i in range(len(names))
             for j in range(i + 1, len(names)) if abs(corr[i, j]) > CORR_LIMIT]
    return {"uncertainty": unc, "t_quantile": tq,
            "correlation": {"order": list(names), "matrix": corr.round(6).tolist()},
            "correlated_pairs": pairs}


def band(gradient: np.ndarray, cov_x: np.ndarray, tq: float) -> np.ndarray:
    """Delta-method half-width t √(g Cov gᵀ) of each predicted point (gradient (n, p))."""
    return tq * np.sqrt(np.clip(np.einsum("ij,jk,ik->i", gradient, cov_x, gradient), 0, None))


def separating_data(J, cov_x, s2, candidates) -> list[dict]:
    """Each candidate (label, J_c rows at the same residual scale) → the worst |corr| with it
    added, best first."""
    out = []
    for label, Jc in candidates:
        A = J.T @ J + Jc.T @ Jc
        cov = s2 * np.linalg.pinv(A, rcond=1e-15, hermitian=True)
        c = correlation(cov)
        worst = float(np.max(np.abs(c - np.diag(np.diag(c))))) if len(c) > 1 else 0.0
        out.append({"data": label, "worst_correlation": worst})
    return sorted(out, key=lambda d: d["worst_correlation"])
