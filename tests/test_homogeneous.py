"""Tests of the exact homogeneous reference states (vlab.materials.homogeneous)."""

from __future__ import annotations

import numpy as np
import pytest

from vlab.materials import LAME_MODELS as MODELS, make_material
from vlab.materials.homogeneous import HomogeneousState, InadmissibleState, biaxial, uniaxial

LMBDA, MU = 1.7, 0.9  # MPa
NU = LMBDA / (2 * (LMBDA + MU))
YOUNG = MU * (3 * LMBDA + 2 * MU) / (LMBDA + MU)
STVK_LIMIT = np.sqrt(1 + 1 / NU)


def material(name: str):
    return make_material(name, LMBDA, MU)


@pytest.mark.parametrize("name", list(MODELS))
def test_uniaxial_at_unit_stretch_is_the_unloaded_state(name):
    s = uniaxial(material(name), 1.0)
    assert isinstance(s, HomogeneousState)
    assert s.lateral_stretch == 1.0
    np.testing.assert_array_equal(s.F, np.eye(3))
    np.testing.assert_allclose(s.P, 0.0, atol=1e-15)


@pytest.mark.parametrize("stretch", [0.6, 0.9, 1.001, 1.3, 1.8])
@pytest.mark.parametrize("name", list(MODELS))
def test_uniaxial_state_has_traction_free_lateral_faces(name, stretch):
    s = uniaxial(material(name), stretch)
    assert s.F.shape == s.P.shape == (3, 3)
    np.testing.assert_allclose(s.F, np.diag([stretch, s.lateral_stretch, s.lateral_stretch]))
    assert s.lateral_stretch > 0
    assert abs(s.P[1, 1]) <= 1e-12 * MU
    assert abs(s.P[2, 2]) <= 1e-12 * MU
    assert s.nominal_stress == s.P[0, 0]
    assert np.sign(s.nominal_stress) == np.sign(stretch - 1.0)
    # off-diagonal stresses vanish for a diagonal F
    np.testing.assert_allclose(s.P - np.diag(np.diag(s.P)), 0.0, atol=1e-15)


@pytest.mark.parametrize("stretch", [0.5, 0.8, 1.2, 1.5, 2.0, 0.99 * STVK_LIMIT])
def test_stvk_uniaxial_matches_the_closed_form_lateral_stretch(stretch):
    s = uniaxial(material("stvk"), stretch)
    assert s.lateral_stretch == pytest.approx(np.sqrt(1 - NU * (stretch**2 - 1)), rel=1e-13)


@pytest.mark.parametrize("stretch", [0.3, 0.7, 1.2, 2.0, 4.0])
def test_neo_hookean_uniaxial_satisfies_the_closed_form_lateral_equation(stretch):
    t = uniaxial(material("neo-hookean"), stretch).lateral_stretch
    assert MU * (t**2 - 1) + LMBDA * np.log(stretch * t**2) == pytest.approx(0.0, abs=1e-13)


@pytest.mark.parametrize("stretch", [0.3, 0.7, 1.2, 2.0, 4.0])
def test_stvk_volumetric_uniaxial_matches_the_closed_form_lateral_stretch(stretch):
    eta = LMBDA / 2
    t = uniaxial(material("stvk-volumetric"), stretch).lateral_stretch
    t_ref = np.sqrt((2 * eta * stretch + MU) / (2 * eta * stretch**2 + MU))
    assert t == pytest.approx(t_ref, rel=1e-13)


@pytest.mark.parametrize("stretch", [0.5, 1.5, 3.0])
def test_linear_uniaxial_is_exactly_hookes_law(stretch):
    s = uniaxial(material("linear"), stretch)
    assert s.lateral_stretch == pytest.approx(1 - NU * (stretch - 1), rel=1e-14)
    assert s.nominal_stress == pytest.approx(YOUNG * (stretch - 1), rel=1e-13)


@pytest.mark.parametrize("name", list(MODELS))
def test_small_strain_uniaxial_returns_the_input_youngs_modulus_and_poisson_ratio(name):
    d = 1e-6
    s = uniaxial(material(name), 1 + d)
    assert -(s.lateral_stretch - 1) / d == pytest.approx(NU, rel=1e-5)
    assert s.nominal_stress / d == pytest.approx(YOUNG, rel=1e-5)


def test_stvk_uniaxial_beyond_the_limit_stretch_is_inadmissible():
    with pytest.raises(InadmissibleState, match="no admissible state beyond stretch") as exc:
        uniaxial(material("stvk"), 1.01 * STVK_LIMIT)
    assert isinstance(exc.value, ValueError)
    assert "stvk" in str(exc.value)
    # the reported limit is sqrt(1 + 1/nu) (to the printed 6 digits)
    assert f"{STVK_LIMIT:.6g}" in str(exc.value)


@pytest.mark.parametrize("name", ["linear", "stvk-volumetric", "neo-hookean"])
def test_other_models_have_a_uniaxial_state_at_large_stretch(name):
    s = uniaxial(material(name), 1.5 * STVK_LIMIT)
    assert s.lateral_stretch > 0 and abs(s.P[1, 1]) <= 1e-12 * MU


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf")])
def test_non_positive_or_non_finite_stretch_is_rejected(bad):
    with pytest.raises(ValueError):
        uniaxial(material("neo-hookean"), bad)


@pytest.mark.parametrize("stretch", [0.8, 1.0, 1.25])
@pytest.mark.parametrize("name", list(MODELS))
def test_equibiaxial_state_is_symmetric_and_traction_free_through_the_thickness(name, stretch):
    s = biaxial(material(name), stretch, stretch)
    assert s.P[0, 0] == s.P[1, 1]
    assert abs(s.P[2, 2]) <= 1e-12 * MU
    np.testing.assert_allclose(s.F, np.diag([stretch, stretch, s.lateral_stretch]))
    if stretch == 1.0:
        assert s.lateral_stretch == 1.0


def test_stvk_equibiaxial_matches_the_closed_form_thickness_stretch():
    lam = 1.2
    s = biaxial(material("stvk"), lam, lam)
    t_ref = np.sqrt(1 - 2 * LMBDA * (lam**2 - 1) / (LMBDA + 2 * MU))
    assert s.lateral_stretch == pytest.approx(t_ref, rel=1e-13)


@pytest.mark.parametrize("name", list(MODELS))
def test_biaxial_with_one_unit_stretch_is_plane_stress_in_the_other_direction(name):
    # stretch_y = 1 fixed: the thickness stretch comes from P33 = 0; P00 > 0, P11 > 0 (constrained)
    s = biaxial(material(name), 1.1, 1.0)
    assert abs(s.P[2, 2]) <= 1e-12 * MU
    assert s.P[0, 0] > 0 and s.P[1, 1] > 0


def test_stvk_equibiaxial_beyond_its_limit_is_inadmissible():
    with pytest.raises(InadmissibleState, match="no admissible state beyond stretch"):
        biaxial(material("stvk"), 3.0, 3.0)


def test_homogeneous_state_arrays_are_read_only():
    s = uniaxial(material("stvk"), 1.2)
    with pytest.raises(ValueError):
        s.F[0, 0] = 2.0
    with pytest.raises(ValueError):
        s.P[0, 0] = 2.0
