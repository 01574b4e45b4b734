import numpy as np
import pytest

from vlab.fe.space import DisplacementSpace
from vlab.fe.spring_network import SpringNetwork
from vlab.fe.taylor import random_state, taylor_test
from vlab.geometry.block import block_specimen


def _network(cell: str, order: int = 1, size=(4.0, 3.0, 2.0), h=1.0) -> SpringNetwork:
    space = DisplacementSpace.build(block_specimen(size, h, cell).mesh, order)
    return SpringNetwork(space, E=10.0)


@pytest.mark.parametrize("cell", ["tet", "hex"])
def test_taylor_energy_force_stiffness(cell):
    body = _network(cell)
    u, v = random_state(body, 0.05, seed=3)
    result = taylor_test(body, u, v, h0=0.05)
    assert result.energy_order == pytest.approx(2.0, abs=0.05)
    assert result.force_order == pytest.approx(2.0, abs=0.05)


def test_wrong_stiffness_fails_taylor():
    """The test can fail: a stiffness without the geometric term gives first-order remainders."""
    body = _network("tet")
    u, v = random_state(body, 0.2, seed=1)
    original = body.stiffness
    body.stiffness = lambda ev: 0.5 * original(ev)
    assert taylor_test(body, u, v, h0=0.05).force_order < 1.2


@pytest.mark.parametrize("cell", ["tet", "hex"])
def test_rigid_motion_is_free_and_symmetric_tangent(cell):
    body = _network(cell)
    X = body.space.node_coordinates
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    u = (X @ R.T - X + [1.0, -2.0, 0.5]).ravel()
    ev = body.evaluate(u)
    assert ev.W == pytest.approx(0.0, abs=1e-20)
    assert np.abs(ev.f_int).max() < 1e-12
    K = body.stiffness(ev)
    assert abs(K - K.T).max() < 1e-12


def test_springs_are_element_vertex_pairs():
    assert _network("tet", size=(1.0, 1.0, 1.0), h=1.0).n_springs == 19  # 12 edges + 6 face + 1 body diagonals
    assert _network("hex", size=(1.0, 1.0, 1.0), h=1.0).n_springs == 28


def test_virial_stress_of_uniform_dilatation():
    """Under x = 1.1 X every spring has ε = 0.1; the cell virial stresses are isotropic by the
    cube's symmetry and add up to the network's virial: Σ_e J_e V_e σ_e = Σ_s f_s ⊗ d_s."""
    body = _network("hex")
    X = body.space.node_coordinates
    ev = body.evaluate((0.1 * X).ravel())
    sigma = body.cell_cauchy(ev)
    assert np.allclose(sigma[0, 1], 0.0, atol=1e-12) and np.allclose(sigma[0, 0], sigma[1, 1])
    d = 1.1 * (X[body.b] - X[body.a])
    f = (body.k * 0.1 / np.linalg.norm(d, axis=1))[:, None] * d
    total = np.einsum("si,sj->ij", f, d)
    volume = 1.1**3 * body.space.dx.sum(axis=1)
    assert np.allclose(np.einsum("ije,e->ij", sigma, volume), total)


def test_order_two_mesh_is_rejected_clearly():
    with pytest.raises(ValueError, match="mesh.order = 1"):
        _network("tet", order=2)


def test_network_in_the_lab_has_its_own_poisson_ratio(comparison):
    data = comparison.by_model["spring-network"].data
    assert data["converged"]
    nu, nu_in = data["measured"]["nu"], data["input"]["nu"]
    assert abs(nu - nu_in) > 0.05  # set by the tessellation, not by the input
    assert data["reference"] is None  # no continuum oracle for a network
    checks = comparison.by_model["spring-network"].checks
    assert checks["taylor"]["force_order"] == pytest.approx(2.0, abs=0.05)
