"""The rubber models (Mooney–Rivlin, Yeoh, Ogden, Gent, Arruda–Boyce): Taylor tests of stress
and tangent at random F, F = I, equibiaxial and nearly equal stretches; objectivity; P(I) = 0;
major symmetry; the small-strain E and ν each card implies."""

from __future__ import annotations

import zlib
from dataclasses import replace

import numpy as np
import pytest

from helpers_history import random_rotation
from rubber_cards import NAMES, law
from vlab.materials.homogeneous import uniaxial
from vlab.materials.volumetric import VOLUMETRIC

HS = 5e-3 * 0.5 ** np.arange(6)


def _rotated(diag, rng) -> np.ndarray:
    Q, R = random_rotation(rng), random_rotation(rng)
    return Q @ np.diag(diag) @ R.T


def states(rng) -> dict[str, np.ndarray]:
    F = np.eye(3) + 0.25 * rng.standard_normal((3, 3))
    while np.linalg.det(F) < 0.4:
        F = np.eye(3) + 0.25 * rng.standard_normal((3, 3))
    return {"random": F, "identity": np.eye(3), "equibiaxial": _rotated([1.3, 1.3, 0.65], rng),
            "nearly-equal": _rotated([1.2, 1.2 * (1 + 1e-8), 0.8], rng),
            "all-equal-dilated": 1.1 * random_rotation(rng)}


def slope(rs) -> float:
    """Observed order over the three smallest h. A direction with a small second-order
    coefficient shows order 3 (h³ dominates) before order 2: both mean consistent; an
    inconsistent stress or tangent shows order 1."""
    return float(np.polyfit(np.log(HS[-3:]), np.log(np.maximum(rs[-3:], 1e-300)), 1)[0])


def remainders(m, F, dF):
    F, dF = F[..., None], dF[..., None]
    psi, P, A = m.energy(F), m.stress(F), m.tangent(F)
    r_stress = [abs(float((m.energy(F + h * dF) - psi)[0] - h * np.sum(P * dF))) for h in HS]
    r_tangent = [float(np.abs(m.stress(F + h * dF) - P - h * np.einsum("ijkl...,kl...->ij...", A, dF)).max())
                 for h in HS]
    return r_stress, r_tangent


@pytest.mark.parametrize("state", ["random", "identity", "equibiaxial", "nearly-equal", "all-equal-dilated"])
@pytest.mark.parametrize("volumetric", list(VOLUMETRIC))
@pytest.mark.parametrize("name", NAMES)
def test_stress_and_tangent_pass_the_taylor_test_of_order_two(name, volumetric, state):
    rng = np.random.default_rng(zlib.crc32(f"{name}/{state}".encode()))  # hash() is salted per process
    m = replace(law(name, K=15.0), volumetric=volumetric)
    F = states(rng)[state]
    r_stress, r_tangent = remainders(m, F, rng.standard_normal((3, 3)))
    assert 1.75 < slope(r_stress) < 3.3, r_stress
    assert 1.75 < slope(r_tangent) < 3.3, r_tangent


@pytest.mark.parametrize("name", NAMES)
def test_stress_and_tangent_are_finite_and_continuous_where_stretches_coalesce(name):
    rng = np.random.default_rng(7)
    Q, R = random_rotation(rng), random_rotation(rng)
    F = np.stack([Q @ np.diag([1.3, 1.3 * (1 + d), 0.7]) @ R.T for d in (0.0, 1e-12, 1e-8)], axis=-1)
    m = law(name)
    P, A = m.stress(F), m.tangent(F)
    assert np.all(np.isfinite(P)) and np.all(np.isfinite(A))
    scale = np.abs(A[..., 0]).max()
    assert np.abs(A[..., 1] - A[..., 0]).max() < 1e-9 * scale
    assert np.abs(A[..., 2] - A[..., 0]).max() < 1e-6 * scale


@pytest.mark.parametrize("name", NAMES)
def test_the_unloaded_state_is_stress_free_and_has_zero_energy(name):
    m = law(name)
    I = np.eye(3)[..., None]
    assert np.abs(m.stress(I)).max() < 1e-14
    assert abs(m.energy(I)[0]) < 1e-14


@pytest.mark.parametrize("name", NAMES)
def test_energy_and_stress_are_objective(name):
    rng = np.random.default_rng(3)
    m = law(name)
    F = states(rng)["random"]
    Q = random_rotation(rng)
    QF = (Q @ F)[..., None]
    assert m.energy(QF)[0] == pytest.approx(m.energy(F[..., None])[0], rel=1e-12)
    np.testing.assert_allclose(m.stress(QF)[..., 0], Q @ m.stress(F[..., None])[..., 0], atol=1e-12)


@pytest.mark.parametrize("state", ["random", "identity", "equibiaxial"])
@pytest.mark.parametrize("name", NAMES)
def test_the_tangent_has_major_symmetry(name, state):
    A = law(name).tangent(states(np.random.default_rng(5))[state][..., None])[..., 0]
    np.testing.assert_allclose(A, A.transpose(2, 3, 0, 1), atol=1e-12 * np.abs(A).max())


@pytest.mark.parametrize("name", NAMES)
def test_the_tangent_terms_equal_the_full_tangent(name):
    m = law(name)
    if m.tangent_terms is None:  # a declared capability (vlab.materials.capabilities)
        pytest.skip(f"{name} has no outer-product form (principal stretches: numpy kernel)")
    F = np.stack([states(np.random.default_rng(s))["random"] for s in range(4)], axis=-1)
    np.testing.assert_allclose(m.tangent_terms(F).full(), m.tangent(F), atol=1e-13)
    np.testing.assert_allclose(m.tangent_terms(F).full(), m.isochoric_tangent(F) + (
        m.tangent(F) - m.isochoric_tangent(F)), atol=1e-13)


@pytest.mark.parametrize("bulk", [{"K": 3.0}, {"K": 500.0}, {"D1": 0.5}, {"nu": 0.3}, {"nu": -0.2}])
@pytest.mark.parametrize("name", NAMES)
def test_small_strain_recovers_the_E_and_nu_the_card_implies(name, bulk):
    m = law(name, **bulk)
    E, nu = m.youngs_modulus, m.poisson_ratio
    strains = np.linspace(1e-6, 1e-5, 5)
    states_ = [uniaxial(m, 1.0 + e) for e in strains]
    stress = np.array([s.nominal_stress for s in states_])
    lateral = np.array([s.lateral_stretch - 1.0 for s in states_])
    assert np.polyfit(strains, stress, 1)[0] == pytest.approx(E, rel=1e-4)
    assert -np.polyfit(strains, lateral, 1)[0] == pytest.approx(nu, rel=1e-4, abs=1e-6)
    if "nu" in bulk:
        assert nu == pytest.approx(bulk["nu"], rel=1e-12, abs=1e-15)


def test_the_small_strain_constants_follow_mu0_and_K():
    m = law("mooney-rivlin", K=10.0)
    assert m.mu0 == pytest.approx(0.76)
    assert m.youngs_modulus == pytest.approx(9 * 10.0 * 0.76 / (30.0 + 0.76))
    assert m.poisson_ratio == pytest.approx((30.0 - 1.52) / (2 * 30.76))
    ab = law("arruda-boyce")
    lm = 2.8
    assert ab.mu0 == pytest.approx(0.45 * (1 + 3 / (5 * lm**2) + 99 / (175 * lm**4) + 513 / (875 * lm**6)
                                          + 42039 / (67375 * lm**8)), rel=1e-14)
    assert law("ogden").mu0 == pytest.approx(0.6212) and law("yeoh").mu0 == pytest.approx(0.8)
    assert law("gent").mu0 == 0.5


def _full(form, batch) -> np.ndarray:
    """An IsotropicTangent as the full (3,3,3,3,*batch) array (the kernel's formula, written out)."""
    from vlab.materials.structure import TangentTerms

    kron = [(float(form.c0), 1.0)] if form.c0 else []
    kron += [(1.0, form.S)] if form.S is not None else []
    kron += [(form.B, 1.0)] if form.B is not None else []
    alpha = np.broadcast_to(form.alpha, batch)
    beta = np.broadcast_to(form.beta, batch)
    return TangentTerms(batch, kron=kron, dyad=[((alpha, form.X), form.X)],
                        cross=[((beta, form.X), form.X)]).full()


@pytest.mark.parametrize("name", NAMES)
def test_the_compiled_forms_sum_to_the_tangent(name):
    m = law(name)
    F = np.stack([states(np.random.default_rng(s))[k] for s, k in
                  enumerate(("random", "identity", "equibiaxial", "nearly-equal"))], axis=-1)
    total = sum(_full(f, F.shape[2:]) for f in m.tangent_forms(F))
    np.testing.assert_allclose(total, m.tangent(F), atol=1e-12 * np.abs(m.tangent(F)).max())
