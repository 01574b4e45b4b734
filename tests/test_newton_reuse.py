"""Factorization reuse: the secant (BFGS) memory on chord steps, when another chord step pays,
and the quadratic and cubic load-step predictors."""

import numpy as np
import pytest
import scipy.sparse as sp
from scenes import scene_dict

from vlab.fe.linsolve import factorize
from vlab.fe.newton import NewtonOptions, _chord_pays, _SecantMemory, tangent_at
from vlab.fe.system import System
from vlab.fe.stepping import PathPoint, Stepping, _substep, path_increment
from vlab.loading.grips import grip_loading
from vlab.run import run_scene
from vlab.scene import parse_scene


def _spd(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    a = rng.standard_normal((n, n))
    return a @ a.T + n * np.eye(n)


def test_the_secant_memory_satisfies_the_secant_equation_of_its_last_pair():
    K_old, K = _spd(12, 0), _spd(12, 1)
    factor = factorize(sp.csr_matrix(K_old))
    memory = _SecantMemory(factor)
    rng = np.random.default_rng(2)
    for _ in range(3):
        s = rng.standard_normal(12)
        memory.add(s, K @ s)  # y = K s: a quadratic energy with Hessian K
    s, y, _ = memory.pairs[-1]
    assert np.allclose(memory.direction(-y, factor.solve), s, rtol=1e-10, atol=1e-12)
    assert np.allclose(_SecantMemory(factor).direction(-y, factor.solve), np.linalg.solve(K_old, y))


def test_a_pair_without_positive_curvature_is_dropped_so_the_update_stays_positive_definite():
    memory = _SecantMemory(None)
    memory.add(np.array([1.0, 0.0]), np.array([-1.0, 0.0]))
    assert memory.pairs == []


def test_secant_chord_steps_beat_plain_chord_steps_on_a_quadratic_energy():
    """W = ½uᵀKu − bᵀu with the factor of a neighbouring K̃: the residual after 4 unit steps."""
    K, K_old = _spd(40, 3), _spd(40, 3) * 1.0
    K_old[np.diag_indices(40)] *= 1.3  # a stale tangent: plain chord contracts by ~0.2
    b = np.random.default_rng(4).standard_normal(40)
    factor = factorize(sp.csr_matrix(K_old))

    def run(secant: bool) -> float:
        u, memory = np.zeros(40), _SecantMemory(factor)
        for _ in range(4):
            r = K @ u - b
            du = memory.direction(r, factor.solve)
            if secant:
                memory.add(du, K @ (u + du) - r - b)
            u = u + du
        return float(np.linalg.norm(K @ u - b) / np.linalg.norm(b))

    plain, accelerated = run(False), run(True)
    assert accelerated < 0.1 * plain  # measured: 5.7e-4 vs 8.3e-3


@pytest.mark.parametrize("residuals, pays", [
    ([1e-3, 2e-5], True),         # ρ = 0.02: rtol 1e-8 is log(5e-4)/log(0.02) = 1.9 steps away
    ([1e-3, 2e-4], False),        # ρ = 0.2 > 0.1: exact Newton
    ([1e-2, 1e-3], False),        # ρ = 0.1 but 5 steps to go: one exact step is cheaper
    ([1e-3, 1e-3], False),        # no progress
])
def test_another_chord_step_pays_only_when_it_contracts_and_rtol_is_near(residuals, pays):
    assert _chord_pays(residuals, NewtonOptions(rtol=1e-8)) is pays


@pytest.mark.parametrize("h, dt", [(0.1, 0.1), (0.2, 0.05), (0.05, 0.3), (-0.1, -0.2)])
def test_the_path_increment_is_exact_for_polynomials_of_its_order(h, dt):
    rng = np.random.default_rng(3)
    c = rng.standard_normal((4, 5))                      # u(t) = c0 + c1 t + c2 t² + c3 t³
    t0 = 0.7

    def u(t, degree):
        return sum(c[j] * t**j for j in range(degree + 1))

    def v(t, degree):
        return sum(j * c[j] * t**(j - 1) for j in range(1, degree + 1))

    quadratic = path_increment(h, dt, u(t0 - h, 2), u(t0, 2), v(t0, 2))
    cubic = path_increment(h, dt, u(t0 - h, 3), u(t0, 3), v(t0, 3), v(t0 - h, 3))
    np.testing.assert_allclose(quadratic, u(t0 + dt, 2) - u(t0, 2), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(cubic, u(t0 + dt, 3) - u(t0, 3), rtol=1e-12, atol=1e-12)
    # a cubic path defeats the quadratic: the two predictors differ by c3's term
    assert np.abs(path_increment(h, dt, u(t0 - h, 3), u(t0, 3), v(t0, 3))
                  - (u(t0 + dt, 3) - u(t0, 3))).max() > 1e-3 * np.abs(c[3]).max() * abs(dt) ** 3


def test_the_extrapolating_predictors_start_a_load_step_much_nearer_equilibrium():
    scene = parse_scene(scene_dict(mesh={"cell": "hex", "size": 2.0},
                                   test={"stretch": 1.5, "steps": 5, "grips": "clamped"},
                                   measure={"modulus_points": 0}))
    result = run_scene(scene)
    body, partition = result.solver.body, result.solver.partition
    u_hat = grip_loading(result.specimen, result.space.node_coordinates, scene.test.stretch,
                         scene.test.grips).u_hat
    before, now = result.history.levels[-3], result.history.levels[-2]
    tangent = tangent_at(body, partition, now.evaluation)
    # the path derivative at the earlier state, from its own tangent (what the stepper keeps)
    earlier = tangent_at(body, partition, before.evaluation)
    slope = -earlier.factor.solve(earlier.Kfp @ u_hat[partition.prescribed])
    # a previous state off the path (as past a buckling point, where converged states jump
    # between neighbouring paths): its curvature term is distrusted, the tangent alone is used
    jumped = before.evaluation.u.copy()
    jumped[partition.free] += 5.0
    first = {}
    for name, previous in (("tangent", None),
                           ("quadratic", PathPoint(before.t, before.evaluation.u)),
                           ("cubic", PathPoint(before.t, before.evaluation.u, slope)),
                           ("jumped", PathPoint(before.t, jumped, slope))):
        record = _substep(System(body, partition, u_hat, (1e-9, 10.0)), now.evaluation, tangent, now.t, 1.0,
                          Stepping(np.array([1.0]), newton=NewtonOptions(chord_contraction=0.0)),
                          tangent, previous).record
        first[name] = record.residuals[0]
    # measured on this block: 7.2e-3 (tangent), 7.7e-4 (quadratic), 9.7e-5 (cubic)
    assert first["quadratic"] < 0.2 * first["tangent"]
    assert first["cubic"] < 0.3 * first["quadratic"]
    assert first["jumped"] == pytest.approx(first["tangent"], rel=1e-12)
