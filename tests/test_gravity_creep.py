"""Self-weight against the bar solution; creep under a held force (force control of the grip)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from tests.effects_helpers import scene
from vlab.fe.external_load import body_force_vector
from vlab.materials.homogeneous import uniaxial
from vlab.run import run_scene

RHO, G = 2000.0, 9.81  # kg/m³, m/s²


def _gravity_scene(effects=True, direction="-x"):
    return scene({"stretch": 1.001, "steps": 1}, {"gravity": {"direction": direction}} if effects else None,
                 {"model": "linear", "E": 1.0, "nu": 0.0, "density": RHO},
                 mesh={"size": 2.5})


def test_body_force_vector_sums_to_the_weight():
    r = run_scene(_gravity_scene())
    f = body_force_vector(r.space, [0.0, 0.0, -1.0])
    assert f.reshape(-1, 3).sum(axis=0) == pytest.approx([0.0, 0.0, -1000.0])  # ∫ dV = 10³ mm³


def test_self_weight_of_a_block_held_at_both_ends_matches_the_bar_solution():
    """Linear, ν = 0, roller grips at x = 0 and x = L, gravity along −x: by superposition the
    weight adds u_x(x) = −b x (L − x)/(2E) (b = ρ g) to the stretched state, b L²/(8E) at mid-length,
    and the upper (moving) grip carries half the weight on top of E A (λ − 1)."""
    loaded, plain = run_scene(_gravity_scene()), run_scene(_gravity_scene(effects=False))
    assert loaded.converged and "gravity" not in type(plain.extra["body"]).__name__
    b = RHO * 1e-12 * G * 1e3  # N/mm³
    X = loaded.space.node_coordinates
    du = (loaded.final_displacement - plain.final_displacement).reshape(-1, 3)
    x = X[:, 0]
    exact = -b * x * (10.0 - x) / (2.0 * 1.0)
    assert np.max(np.abs(du[:, 0] - exact)) < 1e-6 * b * 100 / 8
    assert np.min(du[:, 0]) == pytest.approx(-b * 100 / 8, rel=1e-6)
    weight = b * 1000.0
    assert loaded.curve.force[0][-1] - plain.curve.force[0][-1] == pytest.approx(weight / 2, rel=1e-6)


def test_gravity_across_the_axis_leaves_the_axial_force_alone():
    r = run_scene(_gravity_scene(direction="-z"))
    plain = run_scene(_gravity_scene(effects=False))
    assert r.converged
    assert r.curve.force[0][-1] == pytest.approx(plain.curve.force[0][-1], rel=1e-9)


def test_creep_under_a_held_force_rises_monotonically_to_the_long_term_compliance():
    hold = 20
    r = run_scene(scene({"stretch": 1.1, "protocol": "creep", "ramp_time": 0.01, "hold_time": 100.0,
                         "hold_steps": hold}, {"viscoelastic": {"tau": [1.0, 10.0], "beta": [1.0, 0.5]}}))
    assert r.converged, r.history.failure
    force = np.array(r.curve.force[0])[-hold - 1:]
    stretch = np.array(r.curve.stretch[0])[-hold - 1:]
    assert np.allclose(force, force[0], rtol=1e-7)  # the force is held
    assert np.all(np.diff(stretch) > 0)  # and the specimen creeps
    law = r.extra["body"].material
    s_held = force[0] / r.curve.area0[0]
    lam_inf = brentq(lambda lam: uniaxial(law.elastic, lam).nominal_stress - s_held, 1.0, 2.0, xtol=1e-14)
    assert stretch[-1] == pytest.approx(lam_inf, rel=2e-4)
    assert (stretch[-1] - 1.0) > 1.2 * (stretch[0] - 1.0)
    strain = np.array(r.curve.strain[0])[-hold - 1:]
    assert np.all(np.diff(strain) > 0)
