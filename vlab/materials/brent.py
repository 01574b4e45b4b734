"""Brent's bracketed root finder (R. P. Brent, *Algorithms for Minimization without Derivatives*,
1973, ch. 4, procedure *zero*): the algorithm of ``scipy.optimize.brentq``, here so that the
homogeneous oracles of every run do not import scipy.optimize (≈ 0.2 s of a ~1 s command on the
benchmark machine; scipy.optimize pulls in scipy.special, the linear-programming solvers, …).

Each step keeps a bracket [b, c] with g(b) g(c) ≤ 0 and |g(b)| ≤ |g(c)|, and tries inverse
quadratic interpolation through (a, b, c) (the secant through (a, b) when a = c); the step is
taken only if it lands inside the bracket and shrinks it faster than bisection would over the
last two steps, else the step is a bisection. Hence it never leaves the bracket and needs at
most about (log₂((c − b)/δ))² evaluations, and usually superlinearly few. It stops when the
half-width |c − b|/2 is ≤ δ = (xtol + rtol |b|)/2, the tolerance ``brentq`` uses, so both return
the same root to within δ. tests/test_brent.py checks it against ``brentq``.
"""

from __future__ import annotations

from typing import Callable


def brent_root(g: Callable[[float], float], a: float, b: float, xtol: float = 2e-12,
               rtol: float = 8.881784197001252e-16, maxiter: int = 500) -> float:
    """A root of ``g`` in [a, b] where g(a) and g(b) have opposite signs (or one is 0).

    Raises ValueError if they do not, RuntimeError if ``maxiter`` evaluations do not converge."""
    fa, fb = g(a), g(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0.0) == (fb > 0.0):
        raise ValueError(f"brent_root: g({a!r}) = {fa!r} and g({b!r}) = {fb!r} have the same sign")
    c, fc = a, fa
    d = e = b - a  # the last step and the one before it
    for _ in range(maxiter):
        if (fb > 0.0) == (fc > 0.0):  # the root left [b, c]: the bracket is [a, b]
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):  # b is always the best estimate
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        delta = 0.5 * (xtol + rtol * abs(b))
        m = 0.5 * (c - b)
        if fb == 0.0 or abs(m) <= delta:
            return b
        d, e = _step(a, b, c, fa, fb, fc, d, e, m, delta)
        a, fa = b, fb
        b += d if abs(d) > delta else (delta if m > 0.0 else -delta)
        fb = g(b)
    raise RuntimeError(f"brent_root: no convergence in {maxiter} evaluations (bracket [{b!r}, {c!r}])")


def _step(a, b, c, fa, fb, fc, d, e, m, delta):
    """(this step, the last one): inverse quadratic interpolation through (a, b, c), or the
    secant through (a, b) when a = c, accepted only inside the bracket and if it beats half the
    step before last (else the steps could shrink arbitrarily slowly); else bisection, m."""
    if abs(e) < delta or abs(fa) <= abs(fb):
        return m, m
    s = fb / fa
    if a == c:
        p, q = 2.0 * m * s, 1.0 - s
    else:
        q, r = fa / fc, fb / fc
        p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
        q = (q - 1.0) * (r - 1.0) * (s - 1.0)
    if p > 0.0:
        q = -q
    else:
        p = -p
    if 2.0 * p < min(3.0 * m * q - abs(delta * q), abs(e * q)):
        return p / q, d
    return m, m
