"""Straight-line fits over a strain window, as a lab extracts a modulus.

``regression``: least squares y = a + b x over the points with |x| in the window, reporting the
coefficient of determination R² and the standard error of the slope. ``chord``: the slope between
the first and last point inside the window (ISO 527-1 chord modulus, with the recorded points
nearest the window ends).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np


@dataclass(frozen=True)
class LineFit:
    slope: float
    intercept: float
    r2: float
    slope_stderr: float
    n_points: int
    window: tuple[float, float]
    method: str

    def as_dict(self) -> dict:
        return asdict(self)


class FitError(ValueError):
    """Too few points inside the window to fit a line."""


def fit_line(x: np.ndarray, y: np.ndarray, window: tuple[float, float], method: str = "regression") -> LineFit:
    x, y = np.asarray(x, float), np.asarray(y, float)
    inside = (np.abs(x) >= window[0] * (1 - 1e-9)) & (np.abs(x) <= window[1] * (1 + 1e-9))
    xs, ys = x[inside], y[inside]
    if len(xs) < 2:
        raise FitError(f"only {len(xs)} recorded point(s) with |strain| in {window}; need at least 2")
    if method == "chord":
        order = np.argsort(np.abs(xs))
        (x0, y0), (x1, y1) = (xs[order[0]], ys[order[0]]), (xs[order[-1]], ys[order[-1]])
        slope = (y1 - y0) / (x1 - x0)
        return LineFit(float(slope), float(y0 - slope * x0), 1.0, 0.0, 2, tuple(window), "chord")
    design = np.column_stack([np.ones_like(xs), xs])
    coef, *_ = np.linalg.lstsq(design, ys, rcond=None)
    resid = ys - design @ coef
    ss_tot = float(np.sum((ys - ys.mean()) ** 2))
    r2 = 1.0 - float(resid @ resid) / ss_tot if ss_tot > 0 else 1.0
    dof = len(xs) - 2
    sxx = float(np.sum((xs - xs.mean()) ** 2))
    stderr = float(np.sqrt(resid @ resid / dof / sxx)) if dof > 0 and sxx > 0 else 0.0
    return LineFit(float(coef[1]), float(coef[0]), r2, stderr, len(xs), tuple(window), "regression")
