"""[effects.viscoelastic] with [effects.mullins]: one law (vlab.materials.softened_viscoelastic),
consistent derivatives, the two laws it is made of as its limits, the scene grammar, and `vlab run`
of the card `vlab fit` writes for rate-dependent cycles reproducing the fit's forward model."""

from __future__ import annotations

import numpy as np
import pytest

from helpers_history import assert_quadratic, random_F, taylor_ratios
from vlab.fields import SceneError
from vlab.materials.mullins import OgdenRoxburgh
from vlab.materials.neo_hookean import NeoHookean
from vlab.materials.softened_viscoelastic import SoftenedViscoelastic
from vlab.materials.viscoelastic import PronyViscoelastic
from vlab.moduli import from_pair

LAME = from_pair({"E": 10.0, "nu": 0.45})
GROUND = NeoHookean(LAME.lmbda, LAME.mu)


def _law(beta=(0.5, 0.3), m=2.0):
    return SoftenedViscoelastic(GROUND, mullins=OgdenRoxburgh(GROUND, r=2.0, m=m, beta=0.1),
                                prony=PronyViscoelastic(GROUND, tau=(1.0, 10.0), beta=beta))


def _history(law, rng, steps=4):
    """A state after loading to a random F_max in steps of 0.5 s; (F_max, state)."""
    F_max, state = random_F(rng, 0.3), law.initial_state(())
    for k in range(1, steps + 1):
        state = law.update(np.eye(3) + k / steps * (F_max - np.eye(3)), state, 0.5)
    return F_max, state


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_stress_and_tangent_are_consistent_derivatives_on_unloading(seed):
    rng = np.random.default_rng(seed)
    law = _law()
    F_max, state = _history(law, rng)
    F = np.eye(3) + 0.6 * (F_max - np.eye(3))
    assert GROUND.energy(F) < state["W_max"]  # below the maximum: the softening acts
    r_energy, r_stress = taylor_ratios(law, F, state, rng, scale=0.1)
    assert_quadratic(r_energy)
    assert_quadratic(r_stress)


def test_each_law_alone_is_a_limit_of_the_combination():
    rng = np.random.default_rng(7)
    F_max, _ = _history(_law(), rng)
    F = np.eye(3) + 0.5 * (F_max - np.eye(3))
    for combined, alone in ((_law(beta=(0.0, 0.0)), OgdenRoxburgh(GROUND, r=2.0, m=2.0, beta=0.1)),
                            (_law(m=1e300), PronyViscoelastic(GROUND, tau=(1.0, 10.0), beta=(0.5, 0.3)))):
        s1, s2 = combined.initial_state(()), alone.initial_state(())
        for k in range(1, 5):
            G = np.eye(3) + k / 4 * (F_max - np.eye(3))
            s1, s2 = combined.update(G, s1, 0.5), alone.update(G, s2, 0.5)
        a, b = combined.respond(F, s1, 0.5), alone.respond(F, s2, 0.5)
        np.testing.assert_allclose(a.stress, b.stress, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(a.tangent, b.tangent, rtol=1e-12, atol=1e-12)


def _scene(effects, K=None):
    from vlab.scene import parse_scene

    mu = 0.6
    return parse_scene({"name": "j", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
                        "mesh": {"size": 4.0, "order": 1, "cell": "hex"},
                        "material": {"model": "neo-hookean", "mu": mu, "K": K or 1e3 * mu}, "effects": effects,
                        "test": {"kind": "uniaxial", "grips": "roller", "steps": 20, "strain_rate": 0.1,
                                 "protocol": "cyclic", "amplitudes": [1.5, 2.0, 2.5]}})


def test_the_scene_grammar_takes_the_pair_and_refuses_other_pairs():
    both = {"viscoelastic": {"tau": [1.0], "beta": [0.5]}, "mullins": {"r": 2.0, "m": 0.3}}
    assert {s.name for s in _scene(both).effects} == {"viscoelastic", "mullins"}
    with pytest.raises(SceneError, match="one history-dependent law at a time.*combined: mullins with viscoelastic"):
        _scene({"plasticity": {"yield_stress": 1.0}, "mullins": {"r": 2.0, "m": 0.3}})


def test_vlab_run_of_the_fitted_joint_card_is_the_fits_forward_model():
    """`vlab fit` of rate-dependent cycles with both effects, then `vlab run` of its card (K = 1e5
    μ0: the block is nearly incompressible, the fit's history exactly): the run's nominal stress
    against the fit's forward model at the run's own times and stretches."""
    from test_fit_records_joint import _set
    from vlab.identify.fitfile import FitSpec
    from vlab.identify.fitting import fit_any
    from vlab.identify.laws import law_for
    from vlab.identify.records.cyclic import stress_along
    from vlab.identify.records.prony import PronySpec
    from vlab.identify.records.softening import MullinsSpec
    from vlab.identify.states import Constitutive
    from vlab.run import run_scene

    nh = Constitutive(law_for("neo-hookean"), K_over_mu=1e5)
    effects = {"viscoelastic": PronySpec(2), "mullins": MullinsSpec()}
    out = fit_any(FitSpec("j", nh, (_set("slow", 0.05), _set("fast", 0.5)), starts=4, effects=effects))
    card = out.data["card"]
    result = run_scene(_card_scene(card))
    assert result.converged
    c = result.curve
    t, lam, P = np.array(c.time), np.array(c.stretch[0]), c.column("stress")
    pred = np.real(stress_along(nh, effects, out.x[None], "uniaxial", lam, t)[0])
    assert np.max(np.abs(P - pred)) / np.max(np.abs(P)) < 2e-5  # measured 5.8e-6 (5.8e-4 at K = 1000 μ0)


def _card_scene(card):
    from vlab.scene import parse_scene

    return parse_scene({"name": "card", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
                        "mesh": {"size": 4.0, "order": 1, "cell": "hex"}, "material": card["material"],
                        "effects": card["effects"],
                        "test": {"kind": "uniaxial", "grips": "roller", "steps": 20, "strain_rate": 0.1,
                                 "protocol": "cyclic", "amplitudes": [1.5, 2.0, 2.5]}})
