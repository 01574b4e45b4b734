"""Prony-series viscoelasticity: Taylor tests of the law, and the FE tests it must pass on a
homogeneous roller block (one Q1 element) against point integration and analytic limits."""

from __future__ import annotations

import numpy as np
import pytest

from tests.effects_helpers import E, loop_area, point_uniaxial_history, scene
from vlab.materials.homogeneous import uniaxial
from vlab.materials.neo_hookean import NeoHookean
from vlab.materials.viscoelastic import PronyViscoelastic
from vlab.run import run_scene

HS = 10.0 ** -np.arange(1, 5)
LAW = PronyViscoelastic(NeoHookean(1.7, 0.9), tau=(0.5, 3.0), beta=(0.7, 1.3))


def _state_after_history(rng):
    state = LAW.initial_state(())
    for dt in (0.2, 0.7):
        state = LAW.update(np.eye(3) + 0.2 * rng.standard_normal((3, 3)), state, dt)
    return state


@pytest.mark.parametrize("dt", [0.0, 0.3, 10.0])
def test_taylor_stress_and_algorithmic_tangent_remainders_fall_quadratically(dt):
    rng = np.random.default_rng(4)
    state = _state_after_history(rng)
    F = np.eye(3) + 0.25 * rng.standard_normal((3, 3))
    dF = rng.standard_normal((3, 3))
    r = LAW.respond(F, state, dt)
    e_psi, e_P = [], []
    for h in HS:
        trial = LAW.respond(F + h * dF, state, dt, with_tangent=False)
        e_psi.append(abs(trial.energy - r.energy - h * np.sum(r.stress * dF)))
        e_P.append(np.linalg.norm(trial.stress - r.stress - h * np.einsum("ijkl,kl->ij", r.tangent, dF)))
    for errors in (e_psi, e_P):
        assert np.polyfit(np.log(HS), np.log(errors), 1)[0] == pytest.approx(2.0, abs=0.1)


def test_respond_and_update_are_vectorised_and_leave_the_state_untouched():
    rng = np.random.default_rng(5)
    F = np.eye(3)[:, :, None, None] + 0.1 * rng.standard_normal((3, 3, 4, 2))
    state = LAW.initial_state((4, 2))
    new = LAW.update(F, state, 0.1)
    assert not np.any(state["Q"]) and new["Q"].shape == (2, 3, 3, 4, 2)
    r = LAW.respond(F, new, 0.1)
    single = LAW.respond(F[:, :, 1, 0], {k: v[..., 1, 0] for k, v in new.items()}, 0.1)
    assert np.allclose(r.tangent[..., 1, 0], single.tangent) and np.allclose(r.energy[1, 0], single.energy)


def test_zero_betas_reproduce_the_ground_law_and_relaxed_history_is_elastic():
    F = np.diag([1.2, 0.9, 0.95])
    inert = PronyViscoelastic(LAW.elastic, tau=(1.0,), beta=(0.0,))
    r = inert.respond(F, inert.update(F, inert.initial_state(()), 0.1), 0.1)
    assert np.array_equal(r.stress, LAW.elastic.stress(F)) and np.array_equal(r.tangent, LAW.elastic.tangent(F))


def _run(test, effects=None):
    return run_scene(scene(test, effects))


def test_all_betas_zero_equals_the_elastic_run():
    test = {"protocol": "load-unload", "ramp_time": 1.0}
    elastic = _run(test)
    inert = _run(test, {"viscoelastic": {"tau": [1.0], "beta": [0.0]}})
    assert inert.converged and type(inert.solver.body).__name__ == "HistoryBody"
    assert np.allclose(inert.curve.force[0], elastic.curve.force[0], rtol=1e-12, atol=1e-12)
    assert np.allclose(inert.curve.strain[0], elastic.curve.strain[0], rtol=1e-12, atol=1e-14)


def _areas(ramp_times, tau=1.0):
    out = []
    for T in ramp_times:
        r = _run({"stretch": 1.02, "protocol": "load-unload", "ramp_time": T, "steps": 20},
                 {"viscoelastic": {"tau": [tau], "beta": [1.0]}})
        assert r.converged
        u = (np.array(r.curve.stretch[0]) - 1.0) * 10.0
        out.append(loop_area(u, np.array(r.curve.force[0])))
    return np.array(out)


def test_hysteresis_loop_is_positive_and_largest_when_the_ramp_takes_about_tau():
    areas = _areas([0.01, 0.1, 1.0, 10.0, 100.0])
    work = 0.5 * E * 0.02**2 * 1000.0  # elastic work to the peak, N·mm (order of magnitude)
    assert np.all(areas > 1e-4 * work)
    peak = int(np.argmax(areas))
    assert peak in (1, 2, 3), areas  # the loss peaks for ramp times ~ τ (ωτ ~ 1)
    assert areas[peak] > 3 * areas[0] and areas[peak] > 3 * areas[-1], areas


def test_relaxation_follows_the_discrete_law_and_decays_to_the_long_term_ground_law():
    tau, beta = (0.5, 5.0), (1.0, 0.5)
    r = _run({"stretch": 1.2, "protocol": "relaxation", "ramp_time": 0.01, "hold_time": 200.0,
              "hold_steps": 30}, {"viscoelastic": {"tau": list(tau), "beta": list(beta)}})
    assert r.converged
    law = r.solver.body.material
    stress = np.array(r.curve.force[0]) / r.curve.area0[0]
    oracle = point_uniaxial_history(law, r.curve.stretch[0], r.curve.time)
    assert np.max(np.abs(stress - oracle)) < 1e-6 * np.max(np.abs(oracle))
    hold = stress[-31:]
    assert np.all(np.diff(hold) < 0)  # relaxes monotonically
    long_term = uniaxial(law.elastic, 1.2).nominal_stress
    assert abs(stress[-1] - long_term) < 1e-4 * long_term

    class Glassy:  # the instantaneous law: ground law + Σβ ψ_iso, no time to relax
        def stress(self, F):
            return law.respond(F, law.initial_state(()), 0.0, with_tangent=False).stress

    glassy = uniaxial(Glassy(), 1.2).nominal_stress
    assert hold[0] == pytest.approx(glassy, rel=0.02) and hold[0] > 1.5 * long_term
