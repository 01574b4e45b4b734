"""Richardson extrapolation of a mesh-dependent quantity q(h) = q* + C h^p + o(h^p).

From three levels h1 < h2 < h3 (finest first) with values q1, q2, q3, the observed order p solves
    (q2 − q3) / (q1 − q2) = (h3^p − h2^p) / (h2^p − h1^p),
which for a constant ratio r = h2/h1 = h3/h2 is p = ln((q3 − q2)/(q2 − q1)) / ln r; then
    q* = q1 + (q1 − q2) h1^p / (h2^p − h1^p).
It is only meaningful when the differences keep their sign (monotone, asymptotic range) and p is
plausible; otherwise ``Extrapolation.valid`` is False and ``reason`` says why.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq

ROUND_OFF = 1e-10  # relative spread below which levels agree to round-off (no trend to fit)
P_RANGE = (0.25, 8.0)


@dataclass(frozen=True)
class Extrapolation:
    value: float | None  # q*, or the finest value when no extrapolation is valid
    order: float | None  # observed p
    valid: bool
    reason: str = ""


def extrapolate(h: list[float], q: list[float]) -> Extrapolation:
    """Extrapolate from the three finest (smallest h) of the given levels."""
    pairs = sorted((hh, qq) for hh, qq in zip(h, q) if qq is not None and math.isfinite(qq))
    if len(pairs) < 3:
        return Extrapolation(pairs[0][1] if pairs else None, None, False, "fewer than three levels")
    (h1, q1), (h2, q2), (h3, q3) = pairs[:3]
    scale = max(abs(q1), abs(q2), abs(q3), 1e-300)
    if max(q1, q2, q3) - min(q1, q2, q3) <= ROUND_OFF * scale:
        return Extrapolation(q1, None, False, "the levels agree to round-off (mesh-independent)")
    d12, d23 = q1 - q2, q2 - q3
    if d12 == 0.0 or d12 * d23 <= 0.0:
        return Extrapolation(q1, None, False, "non-monotone convergence (not in the asymptotic range)")
    ratio = d23 / d12

    def mismatch(p):
        return (h3**p - h2**p) / (h2**p - h1**p) - ratio

    lo, hi = P_RANGE
    if mismatch(lo) * mismatch(hi) > 0:
        return Extrapolation(q1, None, False, f"observed order outside {lo:g}–{hi:g}")
    p = brentq(mismatch, lo, hi, xtol=1e-10)
    return Extrapolation(q1 + d12 * h1**p / (h2**p - h1**p), p, True)
