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
    assert loaded.converged and "gravity" not in type(plain.solver.body).__name__
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
    law = r.solver.body.material
    s_held = force[0] / r.curve.area0[0]
    lam_inf = brentq(lambda lam: uniaxial(law.elastic, lam).nominal_stress - s_held, 1.0, 2.0, xtol=1e-14)
    assert stretch[-1] == pytest.approx(lam_inf, rel=2e-4)
    assert (stretch[-1] - 1.0) > 1.2 * (stretch[0] - 1.0)
    strain = np.array(r.curve.strain[0])[-hold - 1:]
    assert np.all(np.diff(strain) > 0)


def test_creep_ramps_to_the_given_force_under_force_control_and_holds_it():
    """test.force: 0 → 50 N linearly over ramp_time (5 levels), then held 200 s. The long-term
    stretch is the ground law's at that nominal stress (E = 10, ν = 0.3 Neo-Hookean)."""
    from vlab.materials.neo_hookean import NeoHookean
    hold = 12
    for sign, stretch in ((1.0, 1.1), (-1.0, 0.9)):
        s = scene({"stretch": stretch, "protocol": "creep", "ramp_time": 0.5, "hold_time": 200.0,
                   "hold_steps": hold, "force": sign * 50.0, "steps": 5},
                  {"viscoelastic": {"tau": [1.0, 10.0], "beta": [1.0, 0.5]}})
        r = run_scene(s)
        assert r.converged, r.history.failure
        force = np.array(r.curve.force[0])
        np.testing.assert_allclose(force[:5], sign * np.array([10.0, 20.0, 30.0, 40.0, 50.0]), rtol=1e-7)
        np.testing.assert_allclose(force[5:], sign * 50.0, rtol=1e-7)
        np.testing.assert_allclose(r.curve.time[:5], [0.1, 0.2, 0.3, 0.4, 0.5], rtol=1e-12)
        lam = np.array(r.curve.stretch[0])
        assert np.all(sign * np.diff(lam) > 0)  # creeps on under the held load
        m = s.material.moduli
        ground = NeoHookean(m.lmbda, m.mu)
        lam_inf = brentq(lambda x: uniaxial(ground, x).nominal_stress - sign * 0.5, 0.5, 1.5, xtol=1e-14)
        assert sign * (lam_inf - lam[-1]) > 0 and abs(lam[-1] - lam_inf) < 1e-3 * abs(lam_inf - 1)


@pytest.mark.parametrize("test, fragment", [
    ({"protocol": "creep", "strain_rate": 0.1, "hold_time": 5, "force": 10}, "give test.ramp_time"),
    ({"protocol": "creep", "ramp_time": 1, "hold_time": 5, "force": -10}, "test.force must be > 0"),
    ({"protocol": "relaxation", "ramp_time": 1, "hold_time": 5, "force": 10}, "test.force applies to"),
])
def test_creep_force_is_validated(test, fragment):
    from vlab.scene import SceneError
    with pytest.raises(SceneError) as exc:
        scene({"stretch": 1.1, **test}, {"viscoelastic": {"tau": [1.0], "beta": [1.0]}})
    assert fragment in str(exc.value)


def test_hanging_block_under_self_weight_stretches_by_the_bar_solution():
    """Fixed grip at x = 0 on top, gravity along +x towards the lower grip, which is free: held
    by force control at zero force (the roller crosshead only keeps the end face plane, which the
    ν = 0 bar solution does anyway). End displacement ρ g L²/(2E), stress ρ g (L − x)."""
    from vlab.fe.assembly import Partition
    from vlab.fe.space import DisplacementSpace
    from vlab.fe.stepping import Stepping, run_schedule
    from vlab.fe.system import System
    from vlab.loading.grips import grip_loading
    from vlab.run import build_specimen, make_body

    s = _gravity_scene(direction="+x")
    specimen = build_specimen(s)
    space = DisplacementSpace.build(specimen.mesh, 1, 1.0)
    body = make_body(s, space)
    loading = grip_loading(specimen, space.node_coordinates, s.test.stretch, s.test.grips)
    partition = Partition.build(body.pattern, loading.prescribed)
    hanging = Stepping(schedule=np.array([1.0]), force_held=np.array([True]), force_targets=np.array([0.0]))
    history = run_schedule(System(body, partition, loading.u_hat, (1e-12, 10.0)), hanging)
    assert history.failure is None, history.failure
    u = history.levels[-1].evaluation.u.reshape(-1, 3)
    x = space.node_coordinates[:, 0] if space.node_coordinates.shape[1] == 3 else space.node_coordinates[0]
    b, L, E = RHO * 1e-12 * G * 1e3, 10.0, 1.0  # N/mm³, mm, MPa
    exact = b * x * (2 * L - x) / (2 * E)  # u(x) = b x (2L − x)/(2E): u(L) = b L²/(2E)
    assert np.max(u[:, 0]) == pytest.approx(b * L**2 / (2 * E), rel=1e-8)
    np.testing.assert_allclose(u[:, 0], exact, atol=1e-8 * b * L**2 / (2 * E))
