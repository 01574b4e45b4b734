"""Force control on the mixed (three-field, condensed) formulation: the crosshead force is given,
its position is an unknown (vlab/fe/force_control.py), and Newton carries θ with its update and
takes the watchdog's steps as displacement control does (vlab/fe/mixed.py, fe/line_search.py)."""

import pytest

from vlab.run import run_scene
from vlab.scene import parse_scene

MAX_PER_STEP = 6
FORCE = 200.0  # N on the 10 mm block (nominal stress 2 MPa, stretch ≈ 1.18)


def near_incompressible_block(test: dict):
    return parse_scene({
        "name": "force-controlled-mixed",
        "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
        "mesh": {"size": 2.5, "order": 1, "cell": "hex", "formulation": "mixed"},
        "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.4999},
        "test": {"kind": "uniaxial", "grips": "clamped", **test},
        "measure": {"modulus_points": 0},
        "solver": {"rtol": 1e-9},
    })


@pytest.fixture(scope="module")
def force_controlled():
    ramp = {"stretch": 1.3, "protocol": "creep", "ramp_time": 1.0, "hold_time": 1.0, "hold_steps": 1,
            "force": FORCE, "steps": 5}
    result = run_scene(near_incompressible_block(ramp))
    assert result.converged, result.history.failure
    return result


def test_a_force_controlled_near_incompressible_block_converges_in_at_most_six_iterations_per_step(force_controlled):
    ramp = force_controlled.history.levels[:5]  # the force ramp (the hold after it is one level)
    per_step = [level.iterations for level in ramp]
    assert max(per_step) <= MAX_PER_STEP and all(level.cutbacks == 0 for level in ramp), per_step
    assert force_controlled.curve.force[0][4] == pytest.approx(FORCE, rel=1e-9)


def test_the_force_controlled_state_is_the_displacement_controlled_one_at_the_same_load(force_controlled):
    stretch = force_controlled.curve.stretch[0][4]  # where the force ramp ends
    displaced = run_scene(near_incompressible_block({"stretch": float(stretch), "steps": 5}))
    assert displaced.converged, displaced.history.failure
    assert displaced.curve.force[0][-1] == pytest.approx(FORCE, rel=1e-6)
    lateral = force_controlled.curve.transverse_strain[4]
    assert displaced.curve.transverse_strain[-1] == pytest.approx(lateral, rel=1e-6)
