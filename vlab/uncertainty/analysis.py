"""The budget of a quantity Y (E or ν) from paired runs (GUM) and from the Monte Carlo samples.

Linearised GUM (JCGM 100, 5.1.2): sensitivities by central differences of paired runs at ±u_i
(every other input nominal), c_i = (Y(+u_i) − Y(−u_i)) / (2 u_i); contributions u_i(Y) = |c_i| u_i,
u_c(Y)² = Σ u_i(Y)² (independent inputs), share_i = u_i(Y)² / u_c(Y)².

Monte Carlo (JCGM 101): mean ȳ, standard uncertainty u = the sample standard deviation, the
expanded U = k u with k = 2, the 2.5 / 50 / 97.5 % quantiles. Its statistical error: the mean's
u/√N, and u's relative standard error √((β₂ − (N − 3)/(N − 1)) / N) / 2 (β₂ the sample kurtosis;
1/√(2(N − 1)) for a normal Y).

First-order Sobol indices S_i = Var(E[Y | X_i]) / Var(Y), by the binned (ANOVA) estimator: the
samples sorted by X_i into B = max(4, ⌊√N⌋) equal-count bins,
    S_i = (SS_between/N − (B − 1)/N · SS_within/(N − B)) / Var(Y)
(the second term removes the between-bin variance that within-bin scatter alone would give), with
a bootstrap standard error (200 resamples). For a linear model with independent inputs S_i equals
the GUM share; the two are reported side by side.
"""

from __future__ import annotations

import numpy as np

__all__ = ["gum_budget", "monte_carlo", "sobol_first_order"]

K = 2.0
BOOTSTRAP = 200


def gum_budget(sources, values_plus, values_minus) -> tuple[list[dict], float]:
    """Contributions from Y at ±u_i of each source (lists in the sources' order) and u_c(Y)."""
    rows = []
    for s, yp, ym in zip(sources, values_plus, values_minus):
        c = None if yp is None or ym is None else (yp - ym) / (2.0 * s.u)
        rows.append({"input": s.name, "unit": s.unit, "distribution": s.distribution, "half_width": s.half_width,
                     "u_input": s.u, "source": s.source, "sensitivity": c,
                     "u_contribution": None if c is None else abs(c) * s.u})
    total = float(np.sqrt(sum(r["u_contribution"] ** 2 for r in rows if r["u_contribution"] is not None)))
    for r in rows:
        r["share"] = None if r["u_contribution"] is None or total == 0 else r["u_contribution"] ** 2 / total ** 2
    return rows, total


def _sobol(x: np.ndarray, y: np.ndarray, bins: int) -> float:
    order = np.argsort(x, kind="stable")
    groups = np.array_split(y[order], bins)
    n, mean = len(y), float(np.mean(y))
    ss_b = sum(len(g) * (float(np.mean(g)) - mean) ** 2 for g in groups)
    ss_w = sum(float(np.sum((g - np.mean(g)) ** 2)) for g in groups)
    var = float(np.var(y))
    if var == 0:
        return 0.0
    return (ss_b / n - (bins - 1) / n * ss_w / (n - bins)) / var


def sobol_first_order(X: np.ndarray, y: np.ndarray, seed: int = 0) -> list[tuple[float, float]]:
    """(S_i, bootstrap standard error) of each column of X (N × n) for outputs y (N)."""
    n = len(y)
    bins = max(4, int(np.sqrt(n)))
    if n < 2 * bins:
        return [(float("nan"), float("nan"))] * X.shape[1]
    rng = np.random.default_rng(seed)
    boot = [rng.integers(0, n, n) for _ in range(BOOTSTRAP)]
    out = []
    for j in range(X.shape[1]):
        s = _sobol(X[:, j], y, bins)
        err = float(np.std([_sobol(X[b, j], y[b], bins) for b in boot], ddof=1))
        out.append((float(s), err))
    return out


def monte_carlo(y: np.ndarray) -> dict:
    """Mean, u, U (k = 2), quantiles and their statistical errors of the samples y."""
    n = len(y)
    mean = float(np.mean(y))
    u = float(np.std(y, ddof=1)) if n > 1 else 0.0
    if n > 3 and u > 0:
        beta2 = float(np.mean((y - mean) ** 4) / np.mean((y - mean) ** 2) ** 2)
        rel_u = float(np.sqrt(max(beta2 - (n - 3) / (n - 1), 0.0) / n) / 2)
    else:
        rel_u = None
    q = np.quantile(y, [0.025, 0.5, 0.975]) if n else [None] * 3
    return {"mean": mean, "u": u, "U": K * u, "k": K, "samples": n,
            "quantiles": {"2.5%": float(q[0]), "50%": float(q[1]), "97.5%": float(q[2])},
            "statistical_error": {"mean": u / np.sqrt(n) if n else None, "u_relative": rel_u}}
