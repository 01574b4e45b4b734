"""Tests of the hyperelastic material models (vlab.materials) and tensor helpers (vlab.tensor)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from helpers_history import random_rotation
from vlab import tensor
from vlab.materials import LAME_MODELS as MODELS, Material, make_material

LMBDA, MU = 1.7, 0.9  # MPa; nu ≈ 0.327
FINITE_STRAIN = [name for name in MODELS if not make_material(name, LMBDA, MU).is_linear]
HS = 10.0 ** -np.arange(1, 6)  # h = 1e-1 ... 1e-5


def material(name: str) -> Material:
    return make_material(name, LMBDA, MU)


def apply(A: np.ndarray, dF: np.ndarray) -> np.ndarray:
    """A : dF for a single (unbatched) tangent."""
    return np.einsum("ijkl,kl->ij", A, dF)


def deformation(kind: str, rng: np.random.Generator) -> np.ndarray:
    """A deformation gradient near (not at) the identity, or a moderately large one (det > 0)."""
    scale = {"near-identity": 1e-3, "large": 0.3}[kind]
    while True:
        F = np.eye(3) + scale * rng.standard_normal((3, 3))
        if np.linalg.det(F) > 0.3:
            return F


def slope(hs: np.ndarray, rs: np.ndarray) -> float:
    return float(np.polyfit(np.log(hs), np.log(rs), 1)[0])


def ideal_small_strain_tangent() -> np.ndarray:
    I = np.eye(3)
    return (
        LMBDA * np.einsum("ij,kl->ijkl", I, I)
        + MU * (np.einsum("ik,jl->ijkl", I, I) + np.einsum("il,jk->ijkl", I, I))
    )


# --------------------------------------------------------------------------- registry


def test_registry_lists_the_four_lame_models_with_their_names():
    assert set(MODELS) == {"linear", "stvk", "stvk-volumetric", "neo-hookean"}
    for name in MODELS:
        law = make_material(name, LMBDA, MU)
        assert law.name == name
        assert law.is_linear == (name == "linear")


def test_make_material_builds_a_frozen_dataclass_with_the_lame_constants():
    m = make_material("neo-hookean", LMBDA, MU)
    assert (m.lmbda, m.mu) == (LMBDA, MU)
    with pytest.raises(AttributeError):
        m.mu = 2.0  # type: ignore[misc]


def test_make_material_rejects_an_unknown_model_naming_the_setting_and_allowed_names():
    with pytest.raises(ValueError) as exc:
        make_material("mooney", LMBDA, MU)
    msg = str(exc.value)
    assert "material.model" in msg and "mooney" in msg
    for name in MODELS:
        assert name in msg


@pytest.mark.parametrize("lmbda, mu", [(1.0, 0.0), (1.0, -1.0), (-1.0, 1.0), (float("nan"), 1.0)])
def test_inadmissible_lame_constants_are_rejected(lmbda, mu):
    with pytest.raises(ValueError):
        make_material("stvk", lmbda, mu)


def test_small_strain_constants_follow_from_the_lame_constants():
    m = material("linear")
    E, nu = m.youngs_modulus, m.poisson_ratio
    assert LMBDA == pytest.approx(E * nu / ((1 + nu) * (1 - 2 * nu)))
    assert MU == pytest.approx(E / (2 * (1 + nu)))


# --------------------------------------------------------------------------- Taylor tests


@pytest.mark.parametrize("kind", ["near-identity", "large"])
@pytest.mark.parametrize("name", list(MODELS))
def test_stress_is_the_derivative_of_the_energy_taylor_remainder_falls_like_h_squared(name, kind):
    rng = np.random.default_rng(1234)
    m = material(name)
    F = deformation(kind, rng)
    dF = rng.standard_normal((3, 3))
    psi0, P0 = m.energy(F), m.stress(F)
    rs = np.array([abs(m.energy(F + h * dF) - psi0 - h * np.sum(P0 * dF)) for h in HS])
    assert slope(HS, rs) > 1.8, rs
    if m.is_linear:
        # quadratic energy: the second-order Taylor expansion is exact
        A0 = m.tangent(F)
        exact = [
            abs(m.energy(F + h * dF) - psi0 - h * np.sum(P0 * dF) - 0.5 * h * h * np.sum(dF * apply(A0, dF)))
            for h in HS
        ]
        assert max(exact) < 1e-10 * (LMBDA + 2 * MU) * np.sum(dF * dF)


@pytest.mark.parametrize("kind", ["near-identity", "large"])
@pytest.mark.parametrize("name", list(MODELS))
def test_tangent_is_the_derivative_of_the_stress_taylor_remainder_falls_like_h_squared(name, kind):
    rng = np.random.default_rng(4321)
    m = material(name)
    F = deformation(kind, rng)
    dF = rng.standard_normal((3, 3))
    P0, A0 = m.stress(F), m.tangent(F)
    rs = np.array([np.linalg.norm(m.stress(F + h * dF) - P0 - h * apply(A0, dF)) for h in HS])
    if m.is_linear:
        scale = np.linalg.norm(apply(A0, dF)) * HS
        assert np.all(rs / scale < 1e-10), rs / scale
    else:
        assert slope(HS, rs) > 1.8, rs


@pytest.mark.parametrize("name", list(MODELS))
def test_stress_and_tangent_are_consistent_in_an_inverted_or_strongly_compressed_state(name):
    # stvk-volumetric's ε-form tangent is also valid for J < 0; NH needs J > 0 so use J ≈ 0.2
    rng = np.random.default_rng(7)
    m = material(name)
    F = np.diag([0.4, 0.7, 0.7]) + 0.05 * rng.standard_normal((3, 3))
    if name == "stvk-volumetric":
        F = F @ np.diag([1.0, 1.0, -1.0])
    dF = rng.standard_normal((3, 3))
    P0, A0 = m.stress(F), m.tangent(F)
    rs = np.array([np.linalg.norm(m.stress(F + h * dF) - P0 - h * apply(A0, dF)) for h in HS[1:]])
    if m.is_linear:
        assert np.all(rs < 1e-12)
    else:
        assert slope(HS[1:], rs) > 1.8, rs


# --------------------------------------------------------------------------- identities


@pytest.mark.parametrize("name", list(MODELS))
def test_the_reference_state_is_stress_and_energy_free(name):
    m = material(name)
    assert m.energy(np.eye(3)) == pytest.approx(0.0, abs=1e-15)
    np.testing.assert_allclose(m.stress(np.eye(3)), 0.0, atol=1e-15)


@pytest.mark.parametrize("name", list(MODELS))
def test_tangent_has_major_symmetry(name):
    rng = np.random.default_rng(11)
    m = material(name)
    F = deformation("large", rng)
    A = m.tangent(F)
    np.testing.assert_allclose(A, A.transpose(2, 3, 0, 1), atol=1e-12 * np.abs(A).max())


@pytest.mark.parametrize("name", list(MODELS))
def test_every_model_linearises_to_the_same_small_strain_law(name):
    A = material(name).tangent(np.eye(3))
    np.testing.assert_allclose(A, ideal_small_strain_tangent(), atol=1e-14)


@pytest.mark.parametrize("name", FINITE_STRAIN)
def test_finite_strain_models_are_objective(name):
    rng = np.random.default_rng(99)
    m = material(name)
    F = deformation("large", rng)
    Q = random_rotation(rng)
    assert m.energy(Q @ F) == pytest.approx(m.energy(F), rel=1e-12)
    np.testing.assert_allclose(m.stress(Q @ F), Q @ m.stress(F), atol=1e-12)


@pytest.mark.parametrize("name", FINITE_STRAIN)
def test_finite_strain_models_carry_no_stress_under_a_rigid_rotation(name):
    Q = random_rotation(np.random.default_rng(5))
    m = material(name)
    assert abs(m.energy(Q)) < 1e-13
    np.testing.assert_allclose(m.stress(Q), 0.0, atol=1e-13)


def test_linear_model_is_not_objective():
    rng = np.random.default_rng(99)
    m = material("linear")
    F = deformation("large", rng)
    Q = random_rotation(rng)
    assert np.linalg.norm(m.stress(Q @ F) - Q @ m.stress(F)) > 1e-2 * MU
    # a pure rotation produces spurious stress and energy
    assert m.energy(Q) > 1e-3 * MU
    assert np.abs(m.stress(Q)).max() > 1e-2 * MU


def test_stvk_volumetric_uses_eta_equal_half_lambda():
    m = material("stvk-volumetric")
    assert m.eta == pytest.approx(LMBDA / 2)
    F = np.diag([1.1, 1.1, 1.1])  # pure dilatation: E = 0.105 I
    J, e = 1.1**3, 0.5 * (1.1**2 - 1)
    assert m.energy(F) == pytest.approx(LMBDA / 2 * (J - 1) ** 2 + MU * 3 * e**2, rel=1e-14)


def test_stvk_volumetric_matches_the_inverse_transpose_form_of_the_tangent():
    # A_vol = 2η J[(2J − 1) G_iJ G_kL − (J − 1) G_iL G_kJ], G = F^-T, checked against the ε-form
    rng = np.random.default_rng(3)
    m = material("stvk-volumetric")
    F = deformation("large", rng)
    G = np.linalg.inv(F).T
    J = np.linalg.det(F)
    eta = m.eta
    E = 0.5 * (F.T @ F - np.eye(3))
    I = np.eye(3)
    A_ref = (
        2 * eta * J * ((2 * J - 1) * np.einsum("ij,kl->ijkl", G, G) - (J - 1) * np.einsum("il,kj->ijkl", G, G))
        + 2 * MU * np.einsum("ik,jl->ijkl", I, E)
        + MU * np.einsum("ik,jl->ijkl", F @ F.T, I)
        + MU * np.einsum("il,kj->ijkl", F, F)
    )
    np.testing.assert_allclose(m.tangent(F), A_ref, atol=1e-12)


# --------------------------------------------------------------------------- batches


@pytest.mark.parametrize("batch", [(), (5,), (4, 3)])
@pytest.mark.parametrize("name", list(MODELS))
def test_batched_evaluation_matches_pointwise_evaluation(name, batch):
    rng = np.random.default_rng(21)
    m = material(name)
    n = int(np.prod(batch, dtype=int))
    Fs = [deformation("large", rng) for _ in range(n)]
    F = np.stack(Fs, axis=-1).reshape((3, 3) + batch)
    psi, P, A = m.energy(F), m.stress(F), m.tangent(F)
    assert psi.shape == batch
    assert P.shape == (3, 3) + batch
    assert A.shape == (3, 3, 3, 3) + batch
    flat_psi = psi.reshape(n)
    flat_P = P.reshape(3, 3, n)
    flat_A = A.reshape(3, 3, 3, 3, n)
    for q, Fq in enumerate(Fs):
        assert flat_psi[q] == pytest.approx(m.energy(Fq), rel=1e-13, abs=1e-15)
        np.testing.assert_allclose(flat_P[..., q], m.stress(Fq), rtol=1e-13, atol=1e-14)
        np.testing.assert_allclose(flat_A[..., q], m.tangent(Fq), rtol=1e-13, atol=1e-14)


@pytest.mark.parametrize("name", list(MODELS))
def test_inputs_are_not_modified_and_outputs_are_writable(name):
    rng = np.random.default_rng(2)
    F = np.stack([deformation("large", rng) for _ in range(3)], axis=-1)
    F0 = F.copy()
    m = material(name)
    for out in (m.energy(F), m.stress(F), m.tangent(F)):
        assert out.flags.writeable
    np.testing.assert_array_equal(F, F0)


def test_malformed_deformation_gradients_are_rejected():
    with pytest.raises(ValueError):
        material("stvk").stress(np.eye(2))


# --------------------------------------------------------------------------- Neo-Hookean at J <= 0


def test_neo_hookean_energy_is_infinite_without_warnings_where_j_is_not_positive():
    m = material("neo-hookean")
    F = np.stack([np.eye(3), np.diag([1.0, 1.0, -1.0]), np.zeros((3, 3)), np.diag([2.0, 0.0, 1.0])], axis=-1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        psi = m.energy(F)
        m.stress(F)
        m.tangent(F)
    assert psi[0] == 0.0
    assert np.all(np.isposinf(psi[1:]))


def test_neo_hookean_energy_grows_without_bound_as_j_tends_to_zero():
    m = material("neo-hookean")
    psis = [m.energy(np.diag([1.0, 1.0, j])) for j in (1e-1, 1e-3, 1e-6)]
    assert psis[0] < psis[1] < psis[2] and np.isfinite(psis[2])


@pytest.mark.parametrize("name", ["linear", "stvk", "stvk-volumetric"])
def test_polynomial_models_have_finite_energy_for_inverted_states(name):
    m = material(name)
    assert np.isfinite(m.energy(np.diag([1.0, 1.0, -0.5])))


# --------------------------------------------------------------------------- tensor helpers


def test_tensor_helpers_match_numpy_on_a_batch():
    rng = np.random.default_rng(8)
    F = rng.standard_normal((3, 3, 4, 2))
    G = rng.standard_normal((3, 3, 4, 2))
    Fm = np.moveaxis(F, (0, 1), (-2, -1))  # (4,2,3,3)
    Gm = np.moveaxis(G, (0, 1), (-2, -1))
    back = lambda X: np.moveaxis(X, (-2, -1), (0, 1))  # noqa: E731
    np.testing.assert_allclose(tensor.det(F), np.linalg.det(Fm), rtol=1e-12)
    np.testing.assert_allclose(tensor.inv(F), back(np.linalg.inv(Fm)), rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(
        tensor.cofactor(F), back(np.linalg.det(Fm)[..., None, None] * np.swapaxes(np.linalg.inv(Fm), -1, -2)),
        rtol=1e-10, atol=1e-10,
    )
    np.testing.assert_allclose(tensor.dot(F, G), back(Fm @ Gm), rtol=1e-12)
    np.testing.assert_allclose(tensor.ddot(F, G), np.sum(Fm * Gm, axis=(-2, -1)), rtol=1e-12)
    np.testing.assert_allclose(tensor.trace(F), np.trace(Fm, axis1=-2, axis2=-1), rtol=1e-12)
    np.testing.assert_array_equal(tensor.transpose(F), back(np.swapaxes(Fm, -1, -2)))
    np.testing.assert_array_equal(tensor.identity_like(F)[..., 1, 0], np.eye(3))
    for fn, spec in ((tensor.dyad, "ij...,kl...->ijkl..."), (tensor.dyad_ik, "ik...,jl...->ijkl..."),
                     (tensor.dyad_il, "il...,jk...->ijkl...")):
        ref = np.einsum(spec, F, G)
        np.testing.assert_allclose(fn(F, G), ref, rtol=1e-12)
        acc = np.ones_like(ref)
        np.testing.assert_allclose(fn(F, G, out=acc), ref + 1.0, rtol=1e-12)
