"""The identification layer's closed forms: exact derivatives, and agreement with the FE library."""

import numpy as np
import pytest

from vlab.identify.jacobian import value_and_jacobian
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, response
from vlab.materials.homogeneous import biaxial, uniaxial
from vlab.materials.neo_hookean import NeoHookean

CARDS = {"neo-hookean": (1, [0.5]), "mooney-rivlin": (1, [0.25, 0.05]), "yeoh": (1, [0.2, -0.01, 0.001]),
         "gent": (1, [0.4, 40.0]), "arruda-boyce": (1, [0.4, 5.0]), "ogden": (3, [0.4, 0.01, 0.02, 1.3, 5.0, -2.0])}
KINDS = ("uniaxial", "equibiaxial", "planar", "biaxial", "simple-shear")


def _x(model, card):
    return np.linalg.solve(model.law.transform, card)


@pytest.mark.parametrize("name", CARDS)
@pytest.mark.parametrize("bulk", ["incompressible", "fixed"])
def test_complex_step_jacobian_matches_central_differences_for_every_model_and_kind(name, bulk):
    terms, card = CARDS[name]
    model = Constitutive(law_for(name, terms), bulk, 80.0 if bulk == "fixed" else None)
    x = _x(model, card)
    lam = np.linspace(0.7, 2.5, 6)
    for kind in KINDS:
        f = lambda X: response(model, X, kind, lam, lam[::-1] if kind == "biaxial" else None)  # noqa: E731
        _, J = value_and_jacobian(f, x)
        h = 1e-6 * np.maximum(1.0, np.abs(x))
        Jfd = np.array([(np.real(f((x + h[j] * e)[None]))[0] - np.real(f((x - h[j] * e)[None]))[0]) / (2 * h[j])
                        for j, e in enumerate(np.eye(len(x)))]).T
        assert np.allclose(J, Jfd, rtol=1e-5, atol=1e-7 * np.max(np.abs(J))), kind


@pytest.mark.parametrize("stretch", [0.6, 1.2, 2.0])
def test_compressible_neo_hookean_matches_the_fe_librarys_homogeneous_states(stretch):
    mu, K = 0.6, 15.0
    material = NeoHookean(lmbda=K - 2 * mu / 3, mu=mu)
    model = Constitutive(law_for("neo-hookean"), "fixed", K)
    P = np.real(response(model, np.array([[mu]]), "uniaxial", [stretch]))[0, 0]
    assert P == pytest.approx(uniaxial(material, stretch).nominal_stress, rel=1e-10)
    P2 = np.real(response(model, np.array([[mu]]), "biaxial", [stretch], [1.3]))[0]
    ref = biaxial(material, stretch, 1.3).P
    assert P2 == pytest.approx([ref[0, 0], ref[1, 1]], rel=1e-10)
    Pe = np.real(response(model, np.array([[mu]]), "equibiaxial", [stretch]))[0, 0]
    assert Pe == pytest.approx(biaxial(material, stretch, stretch).P[0, 0], rel=1e-10)
    sigma = np.real(response(model, np.array([[mu]]), "uniaxial", [stretch], measure="true"))[0, 0]
    assert sigma == pytest.approx(uniaxial(material, stretch).cauchy[0, 0], rel=1e-10)


def test_a_large_bulk_modulus_approaches_the_incompressible_response():
    law = law_for("mooney-rivlin")
    x = _x(Constitutive(law), [0.2, 0.05])
    lam = np.linspace(0.5, 3.0, 7)
    for kind in ("uniaxial", "equibiaxial", "planar"):
        inc = np.real(response(Constitutive(law), x[None], kind, lam))
        comp = np.real(response(Constitutive(law, "fixed", 1e7), x[None], kind, lam))
        assert np.allclose(comp, inc, rtol=1e-5, atol=1e-9)


def test_simple_shear_stress_is_the_textbook_value_for_mooney_rivlin_and_neo_hookean():
    gamma = np.linspace(-1.5, 2.0, 8)
    mr = Constitutive(law_for("mooney-rivlin"))
    tau = np.real(response(mr, _x(mr, [0.3, 0.1])[None], "simple-shear", gamma))[0]
    assert np.allclose(tau, 2 * (0.3 + 0.1) * gamma, rtol=1e-12, atol=1e-14)  # linear in γ, exactly
    nh = Constitutive(law_for("neo-hookean"))
    assert np.allclose(np.real(response(nh, np.array([[0.7]]), "simple-shear", gamma))[0], 0.7 * gamma, rtol=1e-12)


def test_ogden_with_one_term_of_alpha_two_is_neo_hookean():
    lam = np.linspace(0.5, 4.0, 9)
    og = Constitutive(law_for("ogden", 1))
    nh = Constitutive(law_for("neo-hookean"))
    for kind in ("uniaxial", "equibiaxial", "planar"):
        a = np.real(response(og, np.array([[0.45, 2.0]]), kind, lam))
        b = np.real(response(nh, np.array([[0.45]]), kind, lam))
        assert np.allclose(a, b, rtol=1e-12)


def test_initial_shear_modulus_of_each_card_is_the_small_strain_slope():
    eps = 1e-6
    for name, (terms, card) in CARDS.items():
        model = Constitutive(law_for(name, terms))
        P = np.real(response(model, _x(model, card)[None], "uniaxial", [1 + eps]))[0, 0]
        assert P / eps == pytest.approx(3 * model.law.mu0(card), rel=1e-4), name  # E = 3 μ0
