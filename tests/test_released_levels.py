"""Recorded load levels keep no deformation gradient: F is rebuilt from u, bit for bit, when read.

A large run used to hold one F (3·3·n_qp doubles per element) per level; at 48³ Q1 hexes that was
11 × 64 MB of its peak memory (benchmarks/RESULTS.md, cube scaling)."""

import numpy as np

from vlab.fe.stepping import Level
from vlab.run import run_scene
from vlab.scene import parse_scene


def _scene(formulation: str = "displacement", effects: dict | None = None):
    data = {
        "name": "released", "specimen": {"shape": "block", "size": [4.0, 3.0, 3.0]},
        "mesh": {"size": 1.0, "cell": "hex", "formulation": formulation},
        "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.3, "steps": 3},
        "measure": {"modulus_points": 0},
    }
    if effects:
        data["effects"], data["test"]["ramp_time"] = effects, 1.0
    return parse_scene(data)


def test_levels_hold_no_F_and_rebuild_the_solvers_own_bit_for_bit():
    result = run_scene(_scene())
    body = result.solver.body
    levels = result.history.levels
    assert levels and all(lv.state.F is None for lv in levels)
    for lv in levels:
        again = body.evaluate(lv.state.u)
        np.testing.assert_array_equal(lv.evaluation.F, again.F)
        assert lv.evaluation.u is lv.state.u and lv.evaluation.f_int is lv.state.f_int


def test_a_mixed_level_keeps_its_element_unknowns():
    result = run_scene(_scene("mixed"))
    lv = result.history.levels[-1]
    assert lv.state.F is None and lv.evaluation.theta is not None
    np.testing.assert_array_equal(lv.evaluation.F, result.solver.body.gradient(lv.state.u))


def test_a_body_that_cannot_rebuild_F_keeps_it():
    """A history body keys its kept cell fields by the evaluation's identity: its levels stay whole."""
    result = run_scene(_scene(effects={"viscoelastic": {"tau": [1.0], "beta": [0.5]}}))
    lv = result.history.levels[-1]
    assert result.solver.body.gradient is None
    assert lv.state.F is not None and lv.evaluation is lv.state


def test_released_is_idempotent_and_needs_a_gradient():
    F = np.ones((3, 3, 1, 1))
    from vlab.fe.problem import Evaluation

    level = Level(1.0, Evaluation(np.zeros(3), F, 0.0, np.zeros(3), 1.0, (0, 0)), [], 0)
    assert level.released(None) is level
    once = level.released(lambda u: F.copy())
    assert once.state.F is None and once.released(lambda u: 0 * F) is once
    np.testing.assert_array_equal(once.evaluation.F, F)
