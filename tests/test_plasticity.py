"""J2 plasticity (vlab.materials.plasticity) and its Hencky elastic law (vlab.materials.hencky).

Measured (E = 1000 MPa, ν = 0.3 and the laws below): Taylor remainder ratios r(h)/r(h/2) lie
within 4 ± 0.05 for energy→stress and stress→tangent in the elastic and plastic regimes; on the
homogeneous uniaxial path the Kirchhoff stress equals the 1D hardening law σ_y(α) and the
permanent set after unloading equals ln λ_max − τ_max/E to ~1e-12 (exact in log strain).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from helpers_history import Frozen, assert_quadratic, random_F, random_rotation, taylor_ratios
from vlab.materials.hencky import Hencky
from vlab.materials.homogeneous import uniaxial
from vlab.materials.neo_hookean import NeoHookean
from vlab.effects.plasticity import parse_params
from vlab.materials.plasticity import J2Plasticity
from vlab.moduli import from_pair

E, NU = 1000.0, 0.3
LAME = from_pair({"E": E, "nu": NU})
HENCKY = Hencky(LAME.lmbda, LAME.mu)
LINEAR = J2Plasticity(HENCKY, yield_stress=10.0, hardening_modulus=100.0)
VOCE = J2Plasticity(HENCKY, yield_stress=10.0, hardening_modulus=20.0, saturation_stress=8.0,
                    saturation_exponent=30.0)
LAWS = {"linear": LINEAR, "voce": VOCE}


def strained_state(law, rng, scale=0.05):
    """A non-virgin state: two plastic increments along random paths."""
    state = law.initial_state(())
    for _ in range(2):
        state = law.update(random_F(rng, scale), state, 1.0)
    assert state["alpha"] > 0.0
    return state


# --------------------------------------------------------------------------- Taylor tests


@pytest.mark.parametrize("name", list(LAWS))
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_plastic_regime_stress_and_tangent_are_consistent_derivatives(name, seed):
    law, rng = LAWS[name], np.random.default_rng(seed)
    state = strained_state(law, rng)
    F = random_F(rng, 0.08)
    assert law._return(F, state).plastic
    r_energy, r_stress = taylor_ratios(law, F, state, rng)
    assert_quadratic(r_energy)
    assert_quadratic(r_stress)


@pytest.mark.parametrize("name", list(LAWS))
@pytest.mark.parametrize("seed", [4, 5])
def test_elastic_regime_inside_a_hardened_yield_surface_is_consistent(name, seed):
    law, rng = LAWS[name], np.random.default_rng(seed)
    F1 = random_F(rng, 0.05)
    state = law.update(F1, law.initial_state(()), 1.0)
    F = np.eye(3) + 0.7 * (F1 - np.eye(3))  # partial unloading: inside the surface
    assert not law._return(F, state).plastic
    r_energy, r_stress = taylor_ratios(law, F, state, rng, scale=0.1)  # steps stay inside
    assert_quadratic(r_energy)
    assert_quadratic(r_stress)


@pytest.mark.parametrize("scale", [1e-3, 0.3])
def test_hencky_stress_and_tangent_are_consistent_derivatives(scale):
    rng = np.random.default_rng(8)
    F = random_F(rng, scale)
    big = J2Plasticity(HENCKY, yield_stress=1e9)  # never yields: pure Hencky
    r_energy, r_stress = taylor_ratios(big, F, big.initial_state(()), rng)
    assert_quadratic(r_energy)
    assert_quadratic(r_stress)


def test_hencky_tangent_at_coincident_stretches_is_the_limit_of_nearby_ones():
    F0, F1 = np.diag([1.1, 0.95, 0.95]), np.diag([1.1, 0.95, 0.95 + 1e-7])
    np.testing.assert_allclose(HENCKY.tangent(F0), HENCKY.tangent(F1), rtol=1e-6, atol=1e-6)
    I = np.eye(3)
    small = LAME.lmbda * np.einsum("ij,kl->ijkl", I, I) + LAME.mu * (
        np.einsum("ik,jl->ijkl", I, I) + np.einsum("il,jk->ijkl", I, I))
    np.testing.assert_allclose(HENCKY.tangent(I), small, atol=1e-10)


# --------------------------------------------------------------------------- elastic range = Hencky


def test_virgin_elastic_range_equals_the_hencky_law_exactly():
    rng = np.random.default_rng(11)
    F = np.stack([np.eye(3) + 1e-3 * rng.standard_normal((3, 3)) for _ in range(6)], axis=-1)
    state = LINEAR.initial_state((6,))
    res = LINEAR.respond(F, state, 1.0)
    assert not LINEAR._return(F, state).plastic.any()
    np.testing.assert_allclose(res.energy, HENCKY.energy(F), rtol=1e-13, atol=1e-16)
    np.testing.assert_allclose(res.stress, HENCKY.stress(F), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(res.tangent, HENCKY.tangent(F), rtol=1e-12, atol=1e-9)


def test_hardened_elastic_range_is_hencky_of_the_elastic_part():
    rng = np.random.default_rng(12)
    F1 = random_F(rng, 0.05)
    state = LINEAR.update(F1, LINEAR.initial_state(()), 1.0)
    L = np.linalg.cholesky(state["Cp_inv"])
    F = np.eye(3) + 0.8 * (F1 - np.eye(3))
    res = LINEAR.respond(F, state, 1.0)
    assert state["alpha"] > 0 and not LINEAR._return(F, state).plastic
    assert res.energy == pytest.approx(HENCKY.energy(F @ L), rel=1e-12)
    np.testing.assert_allclose(res.stress, HENCKY.stress(F @ L) @ L.T, atol=1e-10)


def test_plastic_flow_is_isochoric():
    rng = np.random.default_rng(13)
    state = strained_state(VOCE, rng, scale=0.2)
    assert np.linalg.det(state["Cp_inv"]) == pytest.approx(1.0, abs=1e-12)


# --------------------------------------------------------------------------- invariance, batches


@pytest.mark.parametrize("name", list(LAWS))
def test_objective_rotated_F_gives_rotated_stress_and_the_same_state(name):
    law, rng = LAWS[name], np.random.default_rng(21)
    state = strained_state(law, rng)
    F, Q = random_F(rng, 0.08), random_rotation(rng)
    a, b = law.respond(F, state, 1.0), law.respond(Q @ F, state, 1.0)
    assert b.energy == pytest.approx(a.energy, rel=1e-12)
    np.testing.assert_allclose(b.stress, Q @ a.stress, atol=1e-10)
    s_a, s_b = law.update(F, state, 1.0), law.update(Q @ F, state, 1.0)
    np.testing.assert_allclose(s_b["Cp_inv"], s_a["Cp_inv"], atol=1e-12)
    assert s_b["alpha"] == pytest.approx(s_a["alpha"], rel=1e-12)


@pytest.mark.parametrize("name", list(LAWS))
def test_isotropic_rotating_the_reference_frame_rotates_the_state(name):
    law, rng = LAWS[name], np.random.default_rng(22)
    state = strained_state(law, rng)
    F, Q = random_F(rng, 0.08), random_rotation(rng)
    turned = {"Cp_inv": Q.T @ state["Cp_inv"] @ Q, "alpha": state["alpha"]}
    a, b = law.respond(F, state, 1.0), law.respond(F @ Q, turned, 1.0)
    assert b.energy == pytest.approx(a.energy, rel=1e-12)
    np.testing.assert_allclose(b.stress, a.stress @ Q, atol=1e-10)


def test_batched_response_and_update_match_pointwise_and_leave_inputs_untouched():
    rng = np.random.default_rng(31)
    Fs = [random_F(rng, 0.06) for _ in range(6)]
    F = np.stack(Fs, axis=-1).reshape(3, 3, 2, 3)
    state = VOCE.update(F * 0.7 + 0.3 * np.eye(3)[:, :, None, None], VOCE.initial_state((2, 3)), 1.0)
    frozen = {k: v.copy() for k, v in state.items()}
    res, new = VOCE.respond(F, state, 1.0), VOCE.update(F, state, 1.0)
    assert res.energy.shape == (2, 3) and res.tangent.shape == (3, 3, 3, 3, 2, 3)
    for q in range(6):
        e, c = divmod(q, 3)
        sq = {k: v[..., e, c] for k, v in state.items()}
        one = VOCE.respond(Fs[q], sq, 1.0)
        assert res.energy[e, c] == pytest.approx(one.energy, rel=1e-12)
        np.testing.assert_allclose(res.stress[..., e, c], one.stress, rtol=1e-11, atol=1e-11)
        np.testing.assert_allclose(res.tangent[..., e, c], one.tangent, rtol=1e-10, atol=1e-8)
        np.testing.assert_allclose(new["alpha"][e, c], VOCE.update(Fs[q], sq, 1.0)["alpha"], rtol=1e-12)
    for k in state:
        np.testing.assert_array_equal(state[k], frozen[k])


def test_inverted_points_get_infinite_energy_and_keep_their_state():
    F = np.stack([np.eye(3), np.diag([1.0, 1.0, -1.0])], axis=-1)
    state = LINEAR.initial_state((2,))
    res = LINEAR.respond(F, state, 1.0)
    assert res.energy[0] == 0.0 and np.isposinf(res.energy[1])
    assert np.isnan(res.stress[..., 1]).all()
    np.testing.assert_array_equal(LINEAR.update(F, state, 1.0)["Cp_inv"], state["Cp_inv"])


# --------------------------------------------------------------------------- 1D oracle


def uniaxial_path(law, stretches):
    """Homogeneous uniaxial stress (lateral stretch solved so P22 = P33 = 0) along ``stretches``."""
    state, rows = law.initial_state(()), []
    for lam in stretches:
        hs = uniaxial(Frozen(law, state), lam)
        state = law.update(hs.F, state, 1.0)
        tau = hs.P[0, 0] * lam  # Kirchhoff τ11 = P11 F11 (diagonal F)
        rows.append((lam, hs.lateral_stretch, tau, float(state["alpha"])))
    return np.array(rows), state


def analytic_uniaxial(law, log_strain):
    """1D law: ln λ = α + σ_y(α)/E on plastic loading (else τ = E ln λ, α = 0): (τ, α)."""
    if log_strain * E <= law.yield_stress:
        return E * log_strain, 0.0
    alpha = brentq(lambda a: a + law.flow_stress(a) / E - log_strain, 0.0, log_strain, xtol=1e-16)
    return law.flow_stress(alpha), alpha


@pytest.mark.parametrize("name", list(LAWS))
def test_uniaxial_loading_follows_the_1d_hardening_law_exactly(name):
    law = LAWS[name]
    stretches = np.linspace(1.0, 1.08, 17)[1:]
    rows, _ = uniaxial_path(law, stretches)
    for lam, t, tau, alpha in rows:
        tau_ref, alpha_ref = analytic_uniaxial(law, np.log(lam))
        assert tau == pytest.approx(tau_ref, rel=1e-10)
        assert alpha == pytest.approx(alpha_ref, rel=1e-9, abs=1e-14)
        # lateral log strain: elastic −ν τ/E plus isochoric plastic −α/2
        assert np.log(t) == pytest.approx(-NU * tau / E - alpha / 2, rel=1e-9)


def test_yield_starts_at_the_initial_yield_stress():
    eps_y = LINEAR.yield_stress / E
    rows, _ = uniaxial_path(LINEAR, np.exp([0.5 * eps_y, 0.999 * eps_y, 1.001 * eps_y]))
    assert rows[1, 3] == 0.0 and rows[2, 3] > 0.0
    assert rows[1, 2] == pytest.approx(0.999 * LINEAR.yield_stress, rel=1e-12)


def test_linear_hardening_slope_in_kirchhoff_stress_against_log_strain():
    stretches = np.exp(np.linspace(0.02, 0.06, 5))
    rows, _ = uniaxial_path(LINEAR, stretches)
    slopes = np.diff(rows[:, 2]) / np.diff(np.log(rows[:, 0]))
    H = LINEAR.hardening_modulus
    np.testing.assert_allclose(slopes, E * H / (E + H), rtol=1e-9)  # 90.909 MPa


@pytest.mark.parametrize("name", list(LAWS))
def test_unloading_leaves_the_permanent_set_of_the_hardening_law(name):
    law = LAWS[name]
    loading = np.linspace(1.0, 1.1, 11)[1:]
    rows, state = uniaxial_path(law, loading)
    lam_max, tau_max, alpha_max = rows[-1, 0], rows[-1, 2], rows[-1, 3]
    # unload elastically: the stretch where the axial stress vanishes at the frozen state
    frozen = Frozen(law, state)
    lam_res = brentq(lambda lam: uniaxial(frozen, lam).nominal_stress, 1.0, lam_max, xtol=1e-15)
    permanent_set = np.log(lam_res)
    assert permanent_set == pytest.approx(np.log(lam_max) - tau_max / E, rel=1e-10)
    assert permanent_set == pytest.approx(alpha_max, rel=1e-10)
    assert permanent_set == pytest.approx(analytic_uniaxial(law, np.log(lam_max))[1], rel=1e-9)
    assert not law._return(uniaxial(frozen, lam_res).F, state).plastic
    # the unloaded block is stress-free with the isochoric lateral set
    assert np.log(uniaxial(frozen, lam_res).lateral_stretch) == pytest.approx(-alpha_max / 2, rel=1e-9)


def test_reloading_is_elastic_up_to_the_previous_flow_stress():
    rows, state = uniaxial_path(LINEAR, np.linspace(1.0, 1.05, 6)[1:])
    tau_prev = rows[-1, 2]
    lam_back = np.exp(rows[-1, 3] + 0.99 * tau_prev / E)
    hs = uniaxial(Frozen(LINEAR, state), lam_back)
    assert not LINEAR._return(hs.F, state).plastic
    assert hs.P[0, 0] * lam_back == pytest.approx(0.99 * tau_prev, rel=1e-10)


# --------------------------------------------------------------------------- parameters


def test_parse_params_builds_a_hencky_plasticity_from_the_ground_law():
    ground = NeoHookean(LAME.lmbda, LAME.mu)
    law = parse_params({"yield_stress": 10, "hardening_modulus": 100.0}, "effects.plasticity", ground)
    assert isinstance(law.elastic, Hencky) and law.elastic.mu == ground.mu
    assert (law.yield_stress, law.hardening_modulus, law.saturation_stress) == (10.0, 100.0, 0.0)


@pytest.mark.parametrize("raw, field", [
    ({}, "effects.plasticity.yield_stress"),
    ({"yield_stress": -1.0}, "effects.plasticity.yield_stress"),
    ({"yield_stress": True}, "effects.plasticity.yield_stress"),
    ({"yield_stress": "10"}, "effects.plasticity.yield_stress"),
    ({"yield_stress": 10, "hardening_modulus": -5}, "effects.plasticity.hardening_modulus"),
    ({"yield_stress": 10, "saturation_stress": float("nan")}, "effects.plasticity.saturation_stress"),
    ({"yield_stress": 10, "saturation_stress": 5.0}, "effects.plasticity.saturation_exponent"),
    ({"yield_stress": 10, "saturation_stress": 5.0, "saturation_exponent": 0}, "effects.plasticity.saturation_exponent"),
])
def test_parse_params_names_the_bad_field_and_its_range(raw, field):
    with pytest.raises(ValueError, match=field.replace(".", r"\.")) as exc:
        parse_params(raw, "effects.plasticity", HENCKY)
    assert "MPa" in str(exc.value) or "exponent" in str(exc.value)


def test_parse_params_rejects_unknown_keys_listing_the_allowed_ones():
    with pytest.raises(ValueError) as exc:
        parse_params({"yield_stres": 10}, "effects.plasticity", HENCKY)
    msg = str(exc.value)
    assert "yield_stres" in msg and "effects.plasticity" in msg
    assert "yield_stress" in msg and "saturation_exponent" in msg
