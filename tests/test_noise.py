"""Instrument noise (vlab.measure.noise): repeatability, the noise model, interval coverage, parameters.

The coverage is measured on the exact uniaxial curve of the linear model (σ = Eε, ε_w = −νε), so
the only error is the noise: 400 seeds, 21 points in the window (0.0005, 0.0025).
"""

from __future__ import annotations

import numpy as np
import pytest

from vlab.materials import make_material
from vlab.materials.homogeneous import uniaxial
from vlab.measure.noise import GaugeLengths, NoiseSpec, elastic_uncertainty, noisy_curve, parse_params
from vlab.measure.recorder import Curve
from vlab.moduli import from_pair

E, NU = 2000.0, 0.35
AREA0, GAUGES = 10.0 * 4.0, GaugeLengths(axial={0: 50.0}, transverse=10.0, thickness=4.0)
WINDOW = (0.0005, 0.0025)
SPEC = NoiseSpec(load_cell_std=0.5, load_cell_resolution=0.01, extensometer_std=5e-4,
                 extensometer_resolution=1e-5, seed=7)


def exact_curve(n=31, max_strain=0.003) -> Curve:
    """Noiseless readings of a 10 x 4 mm bar of the linear model in uniaxial tension."""
    lame = from_pair({"E": E, "nu": NU})
    m = make_material("linear", lame.lmbda, lame.mu)
    c = Curve(stretch={0: []}, force={0: []}, strain={0: []}, area0={0: AREA0})
    for k, eps in enumerate(np.linspace(0.0, max_strain, n)):
        hs = uniaxial(m, 1.0 + eps)
        c.t.append(k / (n - 1))
        c.stretch[0].append(1.0 + eps)
        c.force[0].append(hs.nominal_stress * AREA0)
        c.strain[0].append(eps)
        c.transverse_strain.append(hs.lateral_stretch - 1.0)
        c.thickness_strain.append(hs.lateral_stretch - 1.0)
    return c


CURVE = exact_curve()


def test_the_oracle_curve_is_exactly_linear():
    eps = np.array(CURVE.strain[0][1:])
    np.testing.assert_allclose(CURVE.column("stress")[1:] / eps, E, rtol=1e-12)
    np.testing.assert_allclose(np.array(CURVE.transverse_strain[1:]) / eps, -NU, rtol=1e-12)


def test_a_fixed_seed_repeats_exactly_and_another_seed_differs():
    a, b = noisy_curve(CURVE, SPEC, GAUGES), noisy_curve(CURVE, SPEC, GAUGES)
    assert a == b  # every column, bit for bit
    c = noisy_curve(CURVE, NoiseSpec(**{**SPEC.__dict__, "seed": 8}), GAUGES)
    assert c.force[0] != a.force[0] and c.strain[0] != a.strain[0]
    assert elastic_uncertainty(a, WINDOW, SPEC, GAUGES) == elastic_uncertainty(b, WINDOW, SPEC, GAUGES)


def test_the_noiseless_curve_is_not_modified_and_time_and_crosshead_stay_exact():
    before = exact_curve()
    noisy = noisy_curve(CURVE, SPEC, GAUGES)
    assert CURVE == before
    assert noisy.t == CURVE.t and noisy.stretch == CURVE.stretch and noisy.area0 == CURVE.area0
    assert noisy.force[0] is not CURVE.force[0]


def test_readings_have_the_stated_scatter_and_sit_on_the_resolution_grid():
    spec = NoiseSpec(load_cell_std=2.0, load_cell_resolution=0.5, extensometer_std=1e-3,
                     extensometer_resolution=2e-4, seed=3)
    big = exact_curve(n=4001)
    noisy = noisy_curve(big, spec, GAUGES)
    dF = np.array(noisy.force[0]) - np.array(big.force[0])
    dL = (np.array(noisy.strain[0]) - np.array(big.strain[0])) * 50.0
    # std of noise + rounding: sqrt(s² + r²/12), within ~3 standard errors of a 4001-sample estimate
    assert np.std(dF) == pytest.approx(np.hypot(2.0, 0.5 / np.sqrt(12)), rel=0.05)
    assert np.std(dL) == pytest.approx(np.hypot(1e-3, 2e-4 / np.sqrt(12)), rel=0.05)
    assert abs(np.mean(dF)) < 4 * 2.0 / np.sqrt(4001)
    steps = np.array(noisy.force[0]) / 0.5
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-9)
    elong = np.array(noisy.transverse_strain) * 10.0 / 2e-4
    np.testing.assert_allclose(elong, np.round(elong), atol=1e-6)


def coverage(spec: NoiseSpec, seeds: range) -> tuple[float, float, float]:
    """Fraction of seeds whose interval covers the input E, ν; and the mean relative half-width of E."""
    hit_E = hit_nu = 0
    widths = []
    for seed in seeds:
        s = NoiseSpec(**{**spec.__dict__, "seed": seed})
        u = elastic_uncertainty(noisy_curve(CURVE, s, GAUGES), WINDOW, s, GAUGES)
        hit_E += u.E.covers(E)
        hit_nu += u.nu.covers(NU)
        widths.append((u.E.high - u.E.low) / 2 / E)
    return hit_E / len(seeds), hit_nu / len(seeds), float(np.mean(widths))


def test_the_95_percent_interval_covers_the_input_in_95_percent_of_seeds():
    cov_E, cov_nu, width = coverage(SPEC, range(400))
    # binomial standard deviation of a 400-seed fraction at p = 0.95: 1.1 %
    assert 0.92 <= cov_E <= 0.98, cov_E
    assert 0.92 <= cov_nu <= 0.98, cov_nu
    assert 0.002 < width < 0.02  # the noise matters but does not swamp E (~0.5 %)


def test_the_68_percent_interval_covers_in_68_percent_of_seeds():
    cov_E, cov_nu, _ = coverage(NoiseSpec(**{**SPEC.__dict__, "confidence": 0.68}), range(400))
    assert 0.62 <= cov_E <= 0.74, cov_E  # binomial std 2.3 %
    assert 0.62 <= cov_nu <= 0.74, cov_nu


def test_reliability_and_notes_flag_a_noisy_strain_axis_and_coarse_resolution():
    u = elastic_uncertainty(noisy_curve(CURVE, SPEC, GAUGES), WINDOW, SPEC, GAUGES)
    assert u.reliability > 0.999 and u.note == ""
    bad = NoiseSpec(load_cell_std=0.01, load_cell_resolution=1.0, extensometer_std=0.02, seed=1)
    u = elastic_uncertainty(noisy_curve(CURVE, bad, GAUGES), WINDOW, bad, GAUGES)
    assert u.reliability < 0.7
    assert "biases the slopes low" in u.note and "load cell resolution 1 exceeds" in u.note


def test_biaxial_or_empty_curves_are_not_measured_with_a_reason():
    assert "uniaxial" in elastic_uncertainty(Curve(t=[0.0], stretch={0: [1.0], 1: [1.0]}, kind="biaxial"), WINDOW, SPEC, GAUGES).note
    assert elastic_uncertainty(CURVE, (0.1, 0.2), SPEC, GAUGES).note.startswith("not measured")


def test_parse_params_defaults_and_errors():
    spec = parse_params({"load_cell_std": 0.5, "seed": 42}, "effects.noise")
    assert spec == NoiseSpec(load_cell_std=0.5, seed=42, confidence=0.95)
    for raw, field in (({"load_cell_std": -1}, "load_cell_std"), ({"extensometer_std": "1"}, "extensometer_std"),
                       ({"load_cell_std": 1, "seed": -1}, "seed"), ({"load_cell_std": 1, "seed": 1.5}, "seed"),
                       ({"load_cell_std": 1, "confidence": 1.0}, "confidence"),
                       ({"load_cell_std": 1, "extensometer_resolution": float("inf")}, "extensometer_resolution")):
        with pytest.raises(ValueError, match=rf"effects\.noise\.{field} must be"):
            parse_params(raw, "effects.noise")
    with pytest.raises(ValueError, match="sets no noise"):
        parse_params({"seed": 3}, "effects.noise")
    with pytest.raises(ValueError, match=r"unknown key 'std' in \[effects\.noise\] \(allowed: load_cell_std"):
        parse_params({"std": 1}, "effects.noise")
