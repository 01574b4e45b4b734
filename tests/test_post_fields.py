import numpy as np
import pytest

from vlab.materials import make_material
from vlab.materials.homogeneous import uniaxial
from vlab.post.fields import cauchy, max_principal_stretch, von_mises


def test_cauchy_of_homogeneous_uniaxial_state_is_uniaxial():
    mat = make_material("neo-hookean", 5.769230769, 3.846153846)
    state = uniaxial(mat, 1.4)
    F = np.diag([1.4, state.lateral_stretch, state.lateral_stretch])
    sigma = cauchy(mat.stress(F), F)
    J = np.linalg.det(F)
    assert sigma[0, 0] == pytest.approx(state.P[0, 0] * 1.4 / J)
    assert abs(sigma[1, 1]) < 1e-9 and abs(sigma[2, 2]) < 1e-9
    assert von_mises(sigma) == pytest.approx(abs(sigma[0, 0]))
    assert max_principal_stretch(F) == pytest.approx(1.4)


def test_von_mises_ignores_pressure_and_counts_shear():
    assert von_mises(-3.0 * np.eye(3)) == pytest.approx(0.0, abs=1e-12)
    shear = np.zeros((3, 3))
    shear[0, 1] = shear[1, 0] = 2.0
    assert von_mises(shear) == pytest.approx(np.sqrt(3) * 2.0)


def test_max_principal_stretch_is_rotation_invariant():
    c, s = np.cos(0.3), np.sin(0.3)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    F = R @ np.diag([1.2, 0.9, 1.7])
    assert max_principal_stretch(F) == pytest.approx(1.7)


def test_snapshot_fields_match_the_homogeneous_block(comparison):
    """Roller-gripped block: every cell carries the analytic Cauchy stress and volume ratio."""
    out = comparison.by_model["neo-hookean"]
    ref = out.data["reference"]
    lam, t = out.data["curve"]["stretch"][-1], ref["lateral_stretch"][-1]
    J = lam * t * t
    assert np.allclose(out.snapshot.fields["J"][-1], J, rtol=1e-6)
    assert np.allclose(out.snapshot.fields["von-mises"][-1], ref["stress_x"][-1] * lam / J, rtol=1e-6)
    assert np.allclose(out.snapshot.fields["max-stretch"][-1], lam, rtol=1e-6)
    assert np.allclose(out.snapshot.fields["von-mises"][0], 0.0, atol=1e-12)  # frame 0: unloaded


def test_the_closed_form_largest_eigenvalue_is_lapacks_to_round_off():
    from vlab.post.fields import largest_eigenvalue
    rng = np.random.default_rng(4)
    F = np.eye(3)[:, :, None] + 0.3 * rng.standard_normal((3, 3, 20000))
    Q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    special = [np.eye(3), np.diag([2.0, 2.0, 0.5]), np.diag([0.5, 2.0, 2.0]), Q @ np.diag([1.5, 1.5, 1.5 + 1e-9]) @ Q.T,
               np.diag([1.0, 1.0, 1.0 + 1e-14]), np.zeros((3, 3))]
    C = np.concatenate([np.einsum("kI...,kJ...->IJ...", F, F), np.stack(special, axis=-1)], axis=-1)
    reference = np.linalg.eigvalsh(np.moveaxis(C, -1, 0))[:, -1]
    assert np.allclose(largest_eigenvalue(C), reference, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("gamma", [0.0, 0.3, 1.5, 4.0])
def test_the_max_shear_strain_of_simple_shear_is_its_amount_of_shear(gamma):
    """F = I + γ e1⊗e2: λ± = √(1 + γ²/4) ± γ/2 and λ₂ = 1, so λ₁ − λ₃ = γ; rotated and stacked."""
    from vlab.post.fields import max_shear_strain

    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]])
    F = np.eye(3)
    F[0, 1] = gamma
    batch = np.stack([F, R @ F], axis=-1)  # (3, 3, 2)
    assert max_shear_strain(batch) == pytest.approx([gamma, gamma], abs=1e-12)
    stretched = np.diag([1.4, 0.8, 1.1])  # principal stretches: 1.4 − 0.8
    assert max_shear_strain(stretched[..., None]) == pytest.approx([0.6], rel=1e-12)
