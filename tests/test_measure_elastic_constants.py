"""Measurement recovers known inputs: at small strain every model must return the input E and nu."""

import numpy as np
import pytest
from scenes import scene_dict

from vlab.materials import LAME_MODELS as MODELS
from vlab.measure.fit import FitError, fit_line
from vlab.run import run_scene
from vlab.scene import parse_scene

SMALL = {"modulus_window": [1e-6, 1e-5]}


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("nu", [-0.2, 0.0, 0.3, 0.49])
def test_every_model_returns_input_E_and_nu_at_small_strain(model, nu):
    result = run_scene(parse_scene(scene_dict(material={"model": model, "E": 7.0, "nu": nu},
                                              test={"stretch": 1.002, "steps": 2}, measure=SMALL)))
    assert result.constants.E == pytest.approx(7.0, rel=1e-4)
    assert result.constants.nu == pytest.approx(nu, rel=1e-4, abs=1e-5)
    assert result.constants.E_fit["n_points"] >= 3


@pytest.mark.parametrize("model", MODELS)
def test_compression_test_returns_input_E_and_nu(model):
    result = run_scene(parse_scene(scene_dict(material={"model": model, "E": 3.0, "nu": 0.25},
                                              test={"stretch": 0.998, "steps": 2}, measure=SMALL)))
    assert result.constants.E == pytest.approx(3.0, rel=1e-4)
    assert result.constants.nu == pytest.approx(0.25, rel=1e-4)


@pytest.mark.parametrize("stretch", [[1.002, 1.002], [1.002, 1.0005]])
def test_biaxial_test_returns_input_E_and_nu(stretch):
    result = run_scene(parse_scene(scene_dict(test={"kind": "biaxial", "stretch": stretch, "steps": 2},
                                              measure=SMALL)))
    assert result.constants.E == pytest.approx(10.0, rel=1e-4)
    assert result.constants.nu == pytest.approx(0.3, rel=1e-4)
    assert [a["axis"] for a in result.constants.per_axis] == ["x", "y"]


def test_standard_window_shows_the_bias_of_a_nonlinear_material_honestly():
    # ISO 527 window 0.05-0.25 %: the Neo-Hookean curve already bends, E is low by ~0.2 %.
    result = run_scene(parse_scene(scene_dict(test={"stretch": 1.5, "steps": 5})))
    assert result.constants.E == pytest.approx(10.0, rel=5e-3)
    assert result.constants.E != pytest.approx(10.0, rel=1e-4)
    assert result.constants.E_fit["window"] == (0.0005, 0.0025)


def test_line_fit_recovers_slope_and_reports_quality():
    x = np.linspace(0, 0.003, 13)
    y = 5.0 * x + 1e-4
    fit = fit_line(x, y, (0.0005, 0.0025))
    assert fit.slope == pytest.approx(5.0, rel=1e-12)
    assert fit.r2 == pytest.approx(1.0)
    assert fit.n_points == 9
    chord = fit_line(x, y, (0.0005, 0.0025), "chord")
    assert chord.slope == pytest.approx(5.0, rel=1e-12) and chord.n_points == 2


def test_line_fit_refuses_a_window_with_too_few_points():
    with pytest.raises(FitError, match="need at least 2"):
        fit_line(np.array([0.0, 0.01]), np.array([0.0, 1.0]), (0.0005, 0.0025))


def test_a_test_that_never_reaches_the_window_reports_no_modulus():
    result = run_scene(parse_scene(scene_dict(test={"stretch": 1.0002, "steps": 1})))
    assert result.constants.E is None
    assert "not measured" in result.constants.note
