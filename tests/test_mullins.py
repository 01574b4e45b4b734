"""Ogden–Roxburgh Mullins model (vlab.materials.mullins) over the Neo-Hookean ground law.

Measured (E = 10 MPa, ν = 0.45, r = 2, m = 2 MPa, β = 0.1; cycles to stretch 1.3, 1.6, 1.9 in
steps of 0.05): Taylor ratios → 4 within 0.1 on the unloading and primary branches; at stretch 1.3
after the 1.6 maximum the nominal stress is η = 0.7569 of the first-loading value (1.812 vs
2.394 MPa), after the 1.9 maximum η = 0.5652; beyond the previous maximum the curves coincide to 1e-12.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import erf

from helpers_history import Frozen, assert_quadratic, random_F, random_rotation, taylor_ratios
from vlab.materials.homogeneous import uniaxial
from vlab.effects.mullins import parse_params
from vlab.materials.mullins import OgdenRoxburgh
from vlab.materials.neo_hookean import NeoHookean
from vlab.moduli import from_pair

LAME = from_pair({"E": 10.0, "nu": 0.45})
GROUND = NeoHookean(LAME.lmbda, LAME.mu)
LAW = OgdenRoxburgh(GROUND, r=2.0, m=2.0, beta=0.1)


def loaded_state(rng, scale=0.3):
    F_max = random_F(rng, scale)
    return F_max, LAW.update(F_max, LAW.initial_state(()), 1.0)


# --------------------------------------------------------------------------- derivatives


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_unloading_branch_stress_and_tangent_are_consistent_derivatives(seed):
    rng = np.random.default_rng(seed)
    F_max, state = loaded_state(rng)
    F = np.eye(3) + 0.6 * (F_max - np.eye(3))
    assert GROUND.energy(F) < state["W_max"]
    r_energy, r_stress = taylor_ratios(LAW, F, state, rng, scale=0.1)
    assert_quadratic(r_energy)
    assert_quadratic(r_stress)


@pytest.mark.parametrize("seed", [4, 5])
def test_primary_branch_beyond_the_maximum_equals_the_ground_law(seed):
    rng = np.random.default_rng(seed)
    F_max, state = loaded_state(rng, scale=0.1)
    F = np.eye(3) + 2.0 * (F_max - np.eye(3))
    assert GROUND.energy(F) > state["W_max"]
    res = LAW.respond(F, state, 1.0)
    assert res.energy == pytest.approx(GROUND.energy(F), rel=1e-13)
    np.testing.assert_allclose(res.stress, GROUND.stress(F), rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(res.tangent, GROUND.tangent(F), rtol=1e-13, atol=1e-13)
    r_energy, r_stress = taylor_ratios(LAW, F, state, rng, scale=0.1)
    assert_quadratic(r_energy)
    assert_quadratic(r_stress)


def test_pseudo_energy_is_stationary_in_eta_and_phi_matches_the_erfinv_form():
    rng = np.random.default_rng(6)
    F_max, state = loaded_state(rng, scale=0.1)
    W_max = float(state["W_max"])
    F = np.eye(3) + 0.8 * (F_max - np.eye(3))
    psi0 = float(GROUND.energy(F))
    eta = float(LAW.softening(psi0, W_max))
    assert LAW.respond(F, state, 1.0).energy == pytest.approx(eta * psi0 + LAW.phi(eta, W_max), rel=1e-12)
    d = 1e-6  # ∂(η ψ₀ + φ(η))/∂η = 0 at the model's η (central difference)
    slope = ((eta + d) * psi0 + LAW.phi(eta + d, W_max) - (eta - d) * psi0 - LAW.phi(eta - d, W_max)) / (2 * d)
    assert abs(slope) < 1e-6 * W_max
    assert LAW.phi(1.0, W_max) == 0.0


def test_eta_is_one_on_the_virgin_path_and_at_the_turning_point():
    rng = np.random.default_rng(7)
    virgin = LAW.initial_state(())
    for _ in range(5):
        F = random_F(rng, 0.3)
        np.testing.assert_allclose(LAW.respond(F, virgin, 1.0).stress, GROUND.stress(F), rtol=1e-14)
    F_max, state = loaded_state(rng)
    assert LAW.softening(GROUND.energy(F_max), state["W_max"]) == 1.0
    # softening at rest after the maximum: η(0) = 1 − erf(W_max/(m + βW_max))/r > 1 − 1/r
    eta_rest = LAW.softening(0.0, state["W_max"])
    W = float(state["W_max"])
    assert eta_rest == pytest.approx(1 - erf(W / (LAW.m + LAW.beta * W)) / 2.0, rel=1e-14)
    assert 0.5 < eta_rest < 1.0


# --------------------------------------------------------------------------- cyclic uniaxial test


def cyclic_path(amplitudes, step=0.05):
    """Load 1 → a → 1 for each amplitude a in stretch steps of ``step``;
    rows (stretch, nominal stress, ground nominal stress, W_max before the step, ground ψ₀)."""
    state, rows = LAW.initial_state(()), []
    for a in amplitudes:
        n = int(round((a - 1.0) / step)) + 1
        for lam in np.concatenate([np.linspace(1.0, a, n)[1:], np.linspace(a, 1.0, n)[1:]]):
            hs = uniaxial(Frozen(LAW, state), lam)
            ground = uniaxial(GROUND, lam)
            assert hs.lateral_stretch == pytest.approx(ground.lateral_stretch, rel=1e-12)  # P = ηP₀
            rows.append((lam, hs.nominal_stress, ground.nominal_stress, float(state["W_max"]),
                         float(GROUND.energy(ground.F))))
            state = LAW.update(hs.F, state, 1.0)
    return np.array(rows)


def test_cyclic_test_with_rising_amplitude_softens_below_the_previous_maximum_only():
    amplitudes = (1.3, 1.6, 1.9)
    rows = cyclic_path(amplitudes)
    lam, s, s0, W_max, psi0 = rows.T
    below = psi0 < W_max - 1e-12
    # first loading and everything beyond the previous maximum: the primary (ground) curve
    np.testing.assert_allclose(s[~below], s0[~below], rtol=1e-12)
    # below the previous maximum: strictly under the primary curve, by η of the analytic law
    assert np.all(s[below & (lam > 1.0)] < s0[below & (lam > 1.0)])
    eta = 1 - erf((W_max - psi0) / (LAW.m + LAW.beta * W_max)) / 2.0
    np.testing.assert_allclose(s[below], eta[below] * s0[below], rtol=1e-12, atol=1e-14)
    # stretch 1.3 after the 1.6 maximum (unloading of cycle 2, reloading of cycle 3), then after 1.9
    at = np.flatnonzero(np.isclose(lam, 1.3) & below)
    assert len(at) == 3
    ratio = s[at] / s0[at]
    assert ratio[0] == ratio[1]  # pseudo-elastic: unloading and reloading share one curve
    assert ratio[0] == pytest.approx(0.7569, abs=1e-4) and s0[at[0]] == pytest.approx(2.3936, abs=1e-4)
    assert ratio[2] == pytest.approx(0.5652, abs=1e-4)  # softer after the larger maximum


def test_reloading_curve_rejoins_the_primary_curve_continuously_at_the_previous_maximum():
    rows = cyclic_path((1.5,))
    state = LAW.update(uniaxial(GROUND, 1.5).F, LAW.initial_state(()), 1.0)
    for lam in (1.5 - 1e-6, 1.5, 1.5 + 1e-6):
        s = uniaxial(Frozen(LAW, state), lam).nominal_stress
        assert s == pytest.approx(uniaxial(GROUND, lam).nominal_stress, rel=1e-5)
    assert rows[-1, 1] == pytest.approx(0.0, abs=1e-14)  # back at stretch 1: stress-free


# --------------------------------------------------------------------------- invariance, batches, params


def test_objective_and_isotropic():
    rng = np.random.default_rng(9)
    _, state = loaded_state(rng)
    F, Q = random_F(rng, 0.2), random_rotation(rng)
    base = LAW.respond(F, state, 1.0)
    np.testing.assert_allclose(LAW.respond(Q @ F, state, 1.0).stress, Q @ base.stress, atol=1e-12)
    np.testing.assert_allclose(LAW.respond(F @ Q, state, 1.0).stress, base.stress @ Q, atol=1e-12)
    assert LAW.respond(F @ Q, state, 1.0).energy == pytest.approx(base.energy, rel=1e-12)


def test_batched_and_inadmissible_points():
    rng = np.random.default_rng(10)
    F = np.stack([random_F(rng, 0.3) for _ in range(4)] + [np.diag([1.0, 1.0, -1.0])], axis=-1)
    state = {"W_max": np.array([0.0, 0.5, 2.0, 5.0, 1.0])}
    res, new = LAW.respond(F, state, 1.0), LAW.update(F, state, 1.0)
    for q in range(4):
        one = LAW.respond(F[..., q], {"W_max": state["W_max"][q]}, 1.0)
        assert res.energy[q] == pytest.approx(one.energy, rel=1e-13)
        np.testing.assert_allclose(res.tangent[..., q], one.tangent, rtol=1e-13, atol=1e-13)
    assert np.isposinf(res.energy[4]) and new["W_max"][4] == 1.0
    assert np.all(new["W_max"] >= state["W_max"])


def test_parse_params_and_its_errors():
    law = parse_params({"r": 2, "m": 0.3}, "effects.mullins", GROUND)
    assert (law.r, law.m, law.beta, law.elastic) == (2.0, 0.3, 0.0, GROUND)
    for raw, field in (({"m": 1.0}, "r"), ({"r": 1.0, "m": 1.0}, "r"), ({"r": 2, "m": 0}, "m"),
                       ({"r": 2, "m": 1, "beta": -1}, "beta"), ({"r": 2, "m": "x"}, "m")):
        with pytest.raises(ValueError, match=rf"effects\.mullins\.{field}[ :]"):
            parse_params(raw, "effects.mullins", GROUND)
    with pytest.raises(ValueError, match="allowed: r, m, beta"):
        parse_params({"r": 2, "m": 1, "eta": 1}, "effects.mullins", GROUND)
