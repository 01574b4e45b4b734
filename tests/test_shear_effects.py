"""[effects] in simple shear on the homogeneous kinematic block (every boundary node follows
x = X + γ Y e₁): viscoelastic relaxation toward the long-term G∞ γ, Mullins softening in a
load–unload–reload cycle, J2 plasticity's yield and permanent set, and the caveats that read the
amount of shear instead of a stretch."""

from __future__ import annotations

import numpy as np
import pytest

from vlab.run import run_scene
from vlab.scene import parse_scene

E, NU = 3.0, 0.45
G = E / (2 * (1 + NU))


def shear_scene(test: dict, effects: dict, model: str = "neo-hookean"):
    return parse_scene({
        "name": "shear-effects",
        "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
        "mesh": {"size": 10.0, "cell": "hex"},
        "material": {"model": model, "E": E, "nu": NU},
        "test": {"kind": "simple-shear", "grips": "kinematic"} | test,
        "measure": {"modulus_points": 0},
        "effects": effects})


def curve(scene) -> dict:
    result = run_scene(scene)
    assert result.converged
    return result


def shear_stress(result) -> np.ndarray:
    return np.asarray(result.curve.column("stress", 0))


def test_viscoelastic_shear_stress_relaxes_to_the_long_term_modulus_times_gamma():
    gamma = 0.3
    result = curve(shear_scene({"protocol": "relaxation", "shear": gamma, "ramp_time": 1.0, "hold_time": 100.0,
                                "hold_steps": 20, "steps": 10},
                               {"viscoelastic": {"tau": [1.0, 10.0], "beta": [0.5, 0.3]}}))
    tau = shear_stress(result)
    # Neo-Hookean in simple shear (J = 1): P₁₂ = μ γ exactly; E is the long-term modulus
    assert tau[-1] == pytest.approx(G * gamma, rel=1e-3)
    assert tau.max() > 1.3 * tau[-1]                 # it was stiffer at the end of the ramp
    hold = tau[-20:]
    assert np.all(np.diff(hold) < 0)                  # and relaxed monotonically while held


def test_an_elastic_shear_cycle_retraces_and_a_mullins_material_reloads_softer():
    test = {"protocol": "cyclic", "shear": [0.5, 1.0], "steps": 20}
    elastic = curve(shear_scene(test, {}))
    soft = curve(shear_scene(test, {"mullins": {"r": 2.0, "m": 0.3, "beta": 0.1}}))
    g, tau, tau0 = (np.asarray(soft.curve.stretch[0]), shear_stress(soft), shear_stress(elastic))
    np.testing.assert_allclose(tau0, G * g, rtol=1e-9, atol=1e-12)  # elastic: τ = μ γ on every branch
    first_peak = int(np.argmax(g >= 0.5))
    virgin = np.interp(0.25, g[:first_peak + 1], tau[:first_peak + 1])
    reload = [i for i in range(first_peak + 1, len(g) - 1) if g[i] <= 0.25 < g[i + 1]]  # 0.25 rising again
    assert reload, "the protocol must pass γ = 0.25 on the way to the second amplitude"
    i = reload[0]
    again = np.interp(0.25, g[i:i + 2], tau[i:i + 2])
    assert again < 0.95 * virgin                      # softened below its largest past deformation
    beyond = int(np.argmax(g >= 1.0))
    assert tau[beyond] == pytest.approx(max(tau), rel=1e-12)  # past the old peak: the primary curve again


def test_plasticity_in_shear_yields_near_the_von_mises_shear_yield_stress_and_leaves_a_set():
    sy = 0.3
    result = curve(shear_scene({"protocol": "load-unload", "shear": 0.3, "steps": 10},
                               {"plasticity": {"yield_stress": sy, "hardening_modulus": 0.0}}))
    g, tau = np.asarray(result.curve.stretch[0]), shear_stress(result)
    assert tau.max() == pytest.approx(sy / np.sqrt(3.0), rel=0.03)  # τ_y = σ_y/√3 (finite strain: ~%)
    assert abs(g[-1]) < 1e-12 and tau[-1] < -0.1 * tau.max()        # back at γ = 0 it pulls back: a set


def test_effect_caveats_read_the_amount_of_shear_not_a_stretch():
    scene = shear_scene({"protocol": "monotonic", "shear": 0.01, "steps": 4},
                        {"plasticity": {"yield_stress": 5.0, "hardening_modulus": 0.0}})
    from vlab.effects.build import effect_warnings

    found = " ".join(effect_warnings(scene))
    assert "largest amount of shear 0.01 is below the yield shear strain" in found
