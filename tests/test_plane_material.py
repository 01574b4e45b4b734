"""The plane-stress and plane-strain reductions of every material model (vlab.materials.plane)."""

from __future__ import annotations

import numpy as np
import pytest

from vlab.materials import LAME_MODELS as MODELS, make_material
from vlab.materials.homogeneous import biaxial, uniaxial
from vlab.materials.plane import PlaneStrain, PlaneStress, PlaneStressError, embed

LMBDA, MU = 1.7, 0.9  # MPa, nu ≈ 0.327


def _gradients(n: int = 40, scale: float = 0.2, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    F = np.eye(2)[:, :, None] + scale * rng.standard_normal((2, 2, n))
    return F[:, :, np.linalg.det(np.moveaxis(F, -1, 0)) > 0.6]


def _remainder_orders(model, F: np.ndarray, seed: int = 1) -> tuple[list[float], list[float]]:
    """Observed orders of |ψ(F+h dF) − ψ − h P:dF| and |P(F+h dF) − P − h A:dF| (max over points)."""
    dF = np.random.default_rng(seed).standard_normal(F.shape)
    psi, P, A = model.energy(F), model.stress(F), model.tangent(F)
    rw, rp = [], []
    for h in 1e-2 / 2.0 ** np.arange(5):
        rw.append(np.abs(model.energy(F + h * dF) - psi - h * np.einsum("ij...,ij...->...", P, dF)).max())
        rp.append(np.abs(model.stress(F + h * dF) - P - h * np.einsum("ijkl...,kl...->ij...", A, dF)).max())
    order = lambda r: [float(np.log2(a / b)) for a, b in zip(r, r[1:])]  # noqa: E731
    return order(rw), order(rp)


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("wrapper", [PlaneStress, PlaneStrain])
def test_condensed_stress_and_tangent_pass_the_taylor_test(name, wrapper):
    model = wrapper(make_material(name, LMBDA, MU))
    energy_orders, stress_orders = _remainder_orders(model, _gradients())
    assert np.median(energy_orders) == pytest.approx(2.0, abs=0.1)
    if not model.is_linear:  # the linear law's stress remainder is round-off, no order
        assert np.median(stress_orders) == pytest.approx(2.0, abs=0.1)


@pytest.mark.parametrize("name", list(MODELS))
def test_plane_stress_leaves_no_through_thickness_stress(name):
    base = make_material(name, LMBDA, MU)
    model = PlaneStress(base)
    F = _gradients(scale=0.3).reshape(2, 2, -1, 1)  # batch of any shape
    P3 = base.stress(model.full_gradient(F))
    assert np.abs(P3[2, 2]).max() < 1e-13 * MU
    assert model.stress(F).shape == F.shape and model.tangent(F).shape == (2, 2) + F.shape


@pytest.mark.parametrize("name", list(MODELS))
def test_homogeneous_plane_stress_states_are_the_3d_ones(name):
    """Uniaxial plane stress is the 3D uniaxial state (λ₃ = lateral stretch); biaxial likewise."""
    base = make_material(name, LMBDA, MU)
    model = PlaneStress(base)
    state = uniaxial(base, 1.25)
    F = np.diag([1.25, state.lateral_stretch])
    np.testing.assert_allclose(model.stress(F), state.P[:2, :2], atol=1e-13)
    assert model.out_of_plane_stretch(F) == pytest.approx(state.lateral_stretch, rel=1e-14)
    state = biaxial(base, 1.2, 0.9)
    assert model.out_of_plane_stretch(np.diag([1.2, 0.9])) == pytest.approx(state.lateral_stretch, rel=1e-14)


def test_small_strain_plane_stress_gives_the_reduced_stiffness():
    """Linearised plane stress: Ā = E/(1−ν²) [[1, ν], [ν, 1]] on the normal components."""
    for name in MODELS:
        model = PlaneStress(make_material(name, LMBDA, MU))
        E, nu = model.youngs_modulus, model.poisson_ratio
        A = model.tangent(np.eye(2))
        assert A[0, 0, 0, 0] == pytest.approx(E / (1 - nu**2), rel=1e-12)
        assert A[0, 0, 1, 1] == pytest.approx(E * nu / (1 - nu**2), rel=1e-12)
        assert A[0, 1, 0, 1] == pytest.approx(MU, rel=1e-12)


def test_bisection_fallback_finds_the_root_after_a_bad_warm_start():
    model = PlaneStress(make_material("neo-hookean", LMBDA, MU))
    F = np.diag([1.5, 1.4])[:, :, None]
    model._last = (np.zeros((2, 2, 1)), np.array([1e5]), np.array([True]))  # absurd warm start
    lam = model.out_of_plane_stretch(F)
    lam_b, ok = model._bisection(F.reshape(2, 2, 1))
    assert ok.all() and lam_b[0] == pytest.approx(lam[0], rel=1e-13)
    assert abs(model.base.stress(embed(F, lam))[2, 2, 0]) < 1e-12


def test_stvk_beyond_its_limit_has_no_plane_stress_state():
    """StVK: λ₃² = 1 − ν/(1−ν)(λx² + λy² − 2) has no real root for a large biaxial stretch."""
    model = PlaneStress(make_material("stvk", LMBDA, MU))
    F = np.stack([np.diag([1.1, 1.0]), np.diag([2.0, 1.8])], axis=-1)
    with pytest.raises(PlaneStressError, match="no out-of-plane stretch .* at 1 of 2 point"):
        model.out_of_plane_stretch(F)
    psi = model.energy(F)
    assert np.isfinite(psi[0]) and psi[1] == np.inf  # inadmissible for the line search


def test_plane_strain_keeps_the_thickness():
    base = make_material("neo-hookean", LMBDA, MU)
    F = _gradients()
    np.testing.assert_array_equal(PlaneStrain(base).out_of_plane_stretch(F), 1.0)
    np.testing.assert_allclose(PlaneStrain(base).stress(F), base.stress(embed(F, 1.0))[:2, :2])
