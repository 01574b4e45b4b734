"""The effects plasticity, mullins and noise on the FE path: a roller block of one Q1 element
(homogeneous uniaxial stress) against the point model and the 1D law, plus the scene refusals.

Measured (E = 10 MPa, ν = 0.3, σ_y0 = 0.1 MPa, H = 1 MPa, peak stretch 1.05): the FE
accumulated plastic strain and the stress-free log strain after unloading agree with the 1D
analytic value ln λ_max − τ_max/E = 0.0352638 to < 1e-9 relative (tests below)."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from scipy.optimize import brentq

from tests.effects_helpers import BLOCK, E, point_uniaxial_history, scene
from vlab.effects.build import history_law
from vlab.measure.noise import measure_with_noise
from vlab.materials import make_material
from vlab.materials.homogeneous import uniaxial
from vlab.materials.neo_hookean import NeoHookean
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene

PLASTIC = {"plasticity": {"yield_stress": 0.1, "hardening_modulus": 1.0}}
MULLINS = {"mullins": {"r": 2.0, "m": 0.02}}
SOLVER = {"rtol": 1e-11}
AREA = 100.0  # mm², the 10 × 10 block's section


def _law(s):
    m = s.material.moduli
    return history_law(s, make_material(s.material.model, m.lmbda, m.mu))


def _alpha_1d(law, log_strain):
    """1D hardening law on monotonic loading: ln λ = α + σ_y(α)/E (α = 0 while elastic)."""
    if E * log_strain <= law.yield_stress:
        return 0.0
    return brentq(lambda a: a + law.flow_stress(a) / E - log_strain, 0.0, log_strain, xtol=1e-16)


# --------------------------------------------------------------------------- plasticity


def _plastic_run():
    s = scene({"protocol": "load-unload", "stretch": 1.05, "steps": 20}, PLASTIC, solver=SOLVER)
    r = run_scene(s)
    assert r.converged
    return s, r


def test_plastic_loading_yields_at_the_initial_yield_stress_and_follows_the_hardening_law():
    s, r = _plastic_run()
    law = _law(s)
    lam = np.array(r.curve.stretch[0])
    tau = np.array(r.curve.force[0]) / AREA * lam  # Kirchhoff τ11 = P11 λ (homogeneous block)
    alpha = np.array(r.extra["effects"]["history"]["plastic_strain_max"])
    peak = int(np.argmax(lam))
    eps_y = law.yield_stress / E
    for k in range(peak + 1):
        assert alpha[k] == pytest.approx(_alpha_1d(law, np.log(lam[k])), rel=1e-9, abs=1e-13)
        if np.log(lam[k]) <= eps_y:  # elastic: τ = E ln λ below the yield point
            assert alpha[k] == 0.0 and tau[k] == pytest.approx(E * np.log(lam[k]), rel=1e-9)
        else:  # on the yield surface: τ = σ_y(α)
            assert tau[k] == pytest.approx(law.flow_stress(alpha[k]), rel=1e-9)
    first_plastic = int(np.argmax(alpha > 0))
    assert np.log(lam[first_plastic - 1]) < eps_y < np.log(lam[first_plastic])
    assert tau[first_plastic - 1] < law.yield_stress < tau[first_plastic]


def test_unloading_leaves_the_permanent_set_of_the_point_model():
    s, r = _plastic_run()
    law = _law(s)
    lam = np.array(r.curve.stretch[0])
    eps = np.array(r.curve.strain[0])
    P = np.array(r.curve.force[0]) / AREA
    peak = int(np.argmax(lam))
    alpha_1d = _alpha_1d(law, np.log(lam[peak]))
    assert alpha_1d == pytest.approx(np.log(lam[peak]) - law.flow_stress(alpha_1d) / E, rel=1e-12)
    # point model: the same law at one point, the same stretches, the frozen state at the peak
    point = point_uniaxial_history(law, lam[:peak + 1], np.zeros(peak + 1))
    np.testing.assert_allclose(P[:peak + 1], point, rtol=1e-8, atol=1e-12)
    # elastic unloading branch (force still > 0): the stress-free log strain of each level
    # ln(1 + ε) − τ/E is the permanent set, the same at every level
    unloading = [k for k in range(peak + 1, len(lam)) if P[k] > 0]
    assert len(unloading) >= 3
    permanent = np.log1p(eps[unloading]) - P[unloading] * lam[unloading] / E
    np.testing.assert_allclose(permanent, alpha_1d, rtol=1e-8)
    # and the force really vanishes there: the zero crossing of the recorded branch brackets it
    k0 = next(k for k in range(peak + 1, len(lam)) if P[k] < 0)
    assert np.log(lam[k0]) < alpha_1d < np.log(lam[k0 - 1])


def test_plasticity_history_goes_to_the_vtu_output():
    from vlab.post.snapshot import take_snapshot
    s, r = _plastic_run()
    snap = take_snapshot(r)
    assert "plastic_strain" in snap.fields
    assert snap.fields["plastic_strain"][0].max() == 0.0 and snap.fields["plastic_strain"][-1].max() > 0.03


# --------------------------------------------------------------------------- Mullins


def _mullins_run():
    data = copy.deepcopy(BLOCK)
    del data["test"]["stretch"]  # the cyclic peak is the last amplitude
    data["test"].update({"protocol": "cyclic", "amplitudes": [1.1, 1.2, 1.3], "steps": 30})
    s = parse_scene(data | {"effects": MULLINS, "solver": SOLVER})
    r = run_scene(s)
    assert r.converged
    return s, r


def test_mullins_reloading_lies_below_first_loading_up_to_the_previous_maximum_and_rejoins_beyond():
    s, r = _mullins_run()
    lam = np.array(r.curve.stretch[0])
    P = np.array(r.curve.force[0]) / AREA
    ground = NeoHookean(s.material.moduli.lmbda, s.material.moduli.mu)
    primary = np.array([uniaxial(ground, x).nominal_stress for x in lam])
    # the FE block equals the point model of the same law at every level
    np.testing.assert_allclose(P, point_uniaxial_history(_law(s), lam, np.zeros(len(lam))),
                               rtol=1e-8, atol=1e-12)
    rising = np.concatenate([[True], np.diff(lam) > 0])
    first = np.maximum.accumulate(lam)  # largest stretch so far
    new_max = rising & (lam >= first - 1e-12)
    np.testing.assert_allclose(P[new_max], primary[new_max], rtol=1e-8)  # primary path = ground law
    # second cycle, reloading 1 -> 1.2: below the primary curve up to 1.1, on it beyond
    start = int(np.flatnonzero(np.isclose(lam, 1.0))[0])
    second = np.arange(start + 1, int(np.argmax(lam >= 1.2 - 1e-12)) + 1)
    below = second[lam[second] < 1.1 - 1e-9]
    beyond = second[lam[second] > 1.1 + 1e-9]
    assert len(below) >= 5 and len(beyond) >= 5
    ratio = P[below] / primary[below]
    assert np.all(ratio < 1.0 - 1e-3) and np.all(ratio > 1.0 - 1.0 / 2.0)
    np.testing.assert_allclose(P[beyond], primary[beyond], rtol=1e-8)
    softening = r.extra["effects"]["history"]["softening_min"]
    assert min(softening) < 0.9 and max(softening) == pytest.approx(1.0)


def test_mullins_refuses_a_monotonic_test_and_says_why():
    with pytest.raises(SceneError) as exc:
        scene({"stretch": 1.2}, MULLINS)
    msg = str(exc.value)
    assert "effects.mullins" in msg and "'monotonic'" in msg and "load-unload" in msg and "unloading" in msg


@pytest.mark.parametrize("effects, fragment", [
    ({"plasticity": {}}, "missing required key effects.plasticity.yield_stress"),
    ({"plasticity": {"yield_stress": -1}}, "effects.plasticity.yield_stress must be > 0 (MPa"),
    ({"plasticity": {"yield_stress": 1, "saturation_stress": 2}}, "effects.plasticity.saturation_exponent"),
    ({"plasticity": {"yield_stress": 1, "k": 2}}, "unknown key 'k'"),
    ({"mullins": {"r": 0.5, "m": 1}}, "effects.mullins.r must be > 1 (dimensionless"),
    ({"noise": {}}, "sets no noise"),
    ({"noise": {"load_cell_std": 0.1, "confidence": 1.0}}, "effects.noise.confidence"),
])
def test_bad_parameters_name_the_field(effects, fragment):
    test = {"protocol": "load-unload", "stretch": 1.1}
    with pytest.raises(SceneError) as exc:
        scene(test, effects)
    assert fragment in str(exc.value)


# --------------------------------------------------------------------------- noise

NOISE = {"noise": {"load_cell_std": 0.02, "load_cell_resolution": 0.001, "seed": 7}}
QUIET = {"stretch": 1.01, "steps": 4}
WINDOW_POINTS = {"modulus_points": 20}


def _noisy(seed):
    return run_scene(scene(QUIET, {"noise": {**NOISE["noise"], "seed": seed}}, measure=WINDOW_POINTS))


def test_noise_with_a_fixed_seed_repeats_exactly_and_other_seeds_differ():
    a, b, c = _noisy(7), _noisy(7), _noisy(8)
    assert a.curve.force == b.curve.force and a.constants.E == b.constants.E
    assert a.extra["uncertainty"] == b.extra["uncertainty"]
    assert a.curve.force != c.curve.force and a.constants.E != c.constants.E
    assert a.curve.stretch == c.curve.stretch  # the crosshead encoder is exact


def test_noise_reports_intervals_that_cover_the_input_and_the_noiseless_values():
    r = _noisy(7)
    u = r.extra["uncertainty"]
    assert u["noiseless"]["E"] == pytest.approx(E, rel=3e-3)  # the block's exact curve: E of the input
    assert u["E"]["low"] < E < u["E"]["high"] and u["E"]["value"] == pytest.approx(r.constants.E)
    assert u["E"]["n_points"] >= 10 and u["E"]["confidence"] == 0.95
    assert u["nu"]["value"] == pytest.approx(u["noiseless"]["nu"], rel=1e-9)  # exact extensometers


def test_noise_interval_covers_the_noiseless_modulus_in_about_the_stated_fraction_of_seeds():
    """One solve, 200 seeds of the instruments (measure_with_noise is the run's own path)."""
    s = scene(QUIET, NOISE, measure=WINDOW_POINTS)
    base = run_scene(scene(QUIET, measure=WINDOW_POINTS))
    from dataclasses import replace
    hits = 0
    for seed in range(200):
        spec = replace(s.effect("noise"), seed=seed)
        _, _, u = measure_with_noise(spec, base.curve, base.specimen, s.measure)
        hits += u["E"]["low"] <= u["noiseless"]["E"] <= u["E"]["high"]
    assert 0.90 <= hits / 200 <= 0.99, hits  # 95 % nominal; binomial sd 1.5 %
