"""vlab.materials.brent against scipy.optimize.brentq (the same algorithm, written by others) and
against closed-form roots; the homogeneous oracle that uses it against its closed forms."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from vlab.materials import homogeneous
from vlab.materials.brent import brent_root

EPS = np.finfo(float).eps
CASES = [
    (lambda x: x * x - 2.0, 0.0, 2.0, math.sqrt(2.0)),
    (lambda x: math.cos(x) - x, 0.0, 1.0, None),
    (lambda x: x ** 3, -1.0, 0.5, 0.0),                      # triple root: interpolation stalls
    (lambda x: math.exp(x) - 1e6, 0.0, 50.0, math.log(1e6)),  # steep, far from linear
    (lambda x: math.atan(x - 1e-3), -1e3, 1e4, 1e-3),         # flat tails, wide bracket
    (lambda x: 1.0 if x > 0.3 else -1.0, 0.0, 1.0, 0.3),      # a jump: bisection only
    (lambda x: (x - 1.0) * 1e-300, 0.0, 3.0, 1.0),            # tiny values
]


@pytest.mark.parametrize("g, a, b, exact", CASES)
def test_matches_brentq_and_the_exact_root(g, a, b, exact):
    for xtol, rtol in ((1e-15, 4 * EPS), (1e-8, 1e-8)):
        ours = brent_root(g, a, b, xtol=xtol, rtol=rtol)
        theirs = brentq(g, a, b, xtol=xtol, rtol=rtol, maxiter=500)
        delta = xtol + rtol * abs(theirs)
        assert abs(ours - theirs) <= 2 * delta
        if exact is not None:
            assert abs(ours - exact) <= 2 * delta + 4 * EPS * abs(exact)


def test_bracket_order_endpoints_and_errors():
    g = lambda x: x - 0.25
    assert brent_root(g, 1.0, 0.0) == pytest.approx(0.25, abs=1e-15)
    assert brent_root(g, 0.25, 1.0) == 0.25          # a root at an end is returned as it is
    with pytest.raises(ValueError, match="same sign"):
        brent_root(g, 0.5, 1.0)
    with pytest.raises(RuntimeError, match="no convergence in 3"):
        brent_root(lambda x: math.cos(x) - x, 0.0, 1.0, maxiter=3)


def test_evaluations_stay_within_brents_bound():
    calls = []

    def g(x):
        calls.append(x)
        return math.tanh(20 * (x - 0.123)) + 1e-3 * x

    root = brent_root(g, -10.0, 10.0, xtol=1e-15, rtol=4 * EPS)
    assert all(-10.0 <= x <= 10.0 for x in calls)  # never leaves the bracket
    assert abs(g(root)) < 1e-12
    bisections = math.ceil(math.log2(20 / (1e-15 + 4 * EPS * 0.123)))
    assert len(calls) < bisections // 2  # superlinear on a smooth g, far below bisection's count


def test_homogeneous_oracle_keeps_its_closed_forms():
    from vlab.materials import make_material

    E, nu, lam = 10.0, 0.3, 1.7
    mu, lame = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))
    t = homogeneous.uniaxial(make_material("stvk", lame, mu), 1.05).lateral_stretch
    assert t == pytest.approx(math.sqrt(1 - nu * (1.05 ** 2 - 1)), rel=1e-14)
    t = homogeneous.uniaxial(make_material("neo-hookean", lame, mu), lam).lateral_stretch
    assert mu * (t * t - 1) + lame * math.log(lam * t * t) == pytest.approx(0.0, abs=1e-13)
