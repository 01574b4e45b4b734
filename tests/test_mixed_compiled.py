"""The mixed body's compiled kernels (vlab/fe/compiled_mixed.py for the condensed tangent,
vlab/fe/compiled.py for F and the internal force) against its numpy kernels, the reference."""

import numpy as np
import pytest

from tests.rubber_cards import card
from tests.test_mixed import CASES, _space
from vlab import jit, settings
from vlab.fe.mixed import MixedHyperelasticBody
from vlab.materials.card import build_split_law, parse_material
from vlab.materials.split import SplitLinear, SplitNeoHookean

pytestmark = pytest.mark.skipif(not jit.available(settings.current()), reason="numba is not available")

LAWS = {"neo-hookean": SplitNeoHookean(1e4, 1.0), "linear": SplitLinear(50.0, 2.0),
        "ogden": build_split_law(parse_material(card("ogden", K=500.0)))}


def _pair(cell, order, law):
    space = _space(cell, order)
    return MixedHyperelasticBody(space, law), MixedHyperelasticBody(space, law, kernel="numpy")


@pytest.mark.parametrize("cell,order", CASES)
@pytest.mark.parametrize("name", LAWS)
def test_the_compiled_condensed_tangent_is_the_numpy_one_to_round_off(cell, order, name):
    fast, reference = _pair(cell, order, LAWS[name])
    assert fast.tangent_kernel.startswith("compiled") and reference.tangent_kernel == "numpy"
    u = 0.03 * np.random.default_rng(7).standard_normal(fast.space.n_dofs)
    ev_fast, ev_ref = fast.evaluate(u), reference.evaluate(u)
    scale = np.abs(ev_ref.f_int).max()
    np.testing.assert_allclose(ev_fast.f_int, ev_ref.f_int, rtol=0, atol=1e-12 * scale)
    # away from the projection too: θ carried by the three-field update
    d = np.random.default_rng(8).standard_normal(fast.space.n_dofs)
    moved_fast, moved_ref = fast.advance(ev_fast, d, 1e-3), reference.advance(ev_ref, d, 1e-3)
    assert moved_ref.constraint > 0.0
    for a, b in ((ev_fast, ev_ref), (moved_fast, moved_ref)):
        K, K0 = fast.stiffness(a), reference.stiffness(b)
        assert (K.indptr == K0.indptr).all() and (K.indices == K0.indices).all()
        assert np.abs(K.data - K0.data).max() <= 1e-12 * np.abs(K0.data).max()


@pytest.mark.parametrize("cell,order", CASES)
def test_the_numpy_condensed_tangent_passes_the_taylor_test_of_the_three_field_update(cell, order):
    """f̃(u + h d, θ + h Δθ(d)) − f̃ − h K̃ d = O(h²) with the numpy kernels (with the default,
    compiled ones: tests/test_mixed.py)."""
    _, fast = _pair(cell, order, LAWS["neo-hookean"])
    rng = np.random.default_rng(5)
    u = 0.03 * rng.standard_normal(fast.space.n_dofs)
    d = rng.standard_normal(fast.space.n_dofs)
    d /= np.linalg.norm(d)
    ev = fast.evaluate(u)
    Kd = fast.stiffness(ev) @ d
    remainders = [np.linalg.norm(fast.advance(ev, d, h).f_int - ev.f_int - h * Kd)
                  for h in 1e-3 / 2.0 ** np.arange(5)]
    orders = np.log2(np.array(remainders[:-1]) / np.array(remainders[1:]))
    assert np.median(orders) == pytest.approx(2.0, abs=0.1), remainders
