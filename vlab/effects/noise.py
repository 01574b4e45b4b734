"""``[effects.noise]``: load-cell and extensometer noise and resolution (vlab.measure.noise).

    [effects.noise]
    load_cell_std = 0.05            # N, standard deviation of a force reading
    load_cell_resolution = 0.01     # N, reading step (0 = none)
    extensometer_std = 0.0005       # mm of elongation, standard deviation
    extensometer_resolution = 0.0   # mm
    seed = 1                        # the same seed reproduces every reading bit for bit
    confidence = 0.95               # of the reported intervals of E and ν

A measurement effect: the solve is untouched (no cost in the solver); the recorded curve is
replaced by what noisy instruments report, E and ν are measured from it, and results.json's
``measured.uncertainty`` carries their ``confidence`` intervals (regression standard error,
Student t; fitted on the first loading ramp, where the modulus window lies) together with the
noiseless values measured from the exact curve. Uniaxial tests only report intervals.
"""

from __future__ import annotations

from dataclasses import asdict

from vlab.effects.registry import Effect
from vlab.fields import SceneError
from vlab.measure.elastic_constants import elastic_constants, first_loading
from vlab.measure.noise import (PARAM_KEYS, GaugeLengths, NoiseSpec, elastic_uncertainty, noisy_curve,
                                parse_params)
from vlab.measure.recorder import Curve


def parse(t, material, test) -> NoiseSpec:
    try:
        return parse_params(t.raw, "effects.noise")
    except ValueError as exc:
        raise SceneError(str(exc)) from None


def build(spec: NoiseSpec) -> NoiseSpec:
    return spec


def measure_with_noise(spec: NoiseSpec, curve: Curve, specimen, measure) -> tuple[Curve, object, dict]:
    """(noisy curve, ElasticConstants measured from it, the ``measured.uncertainty`` dict)."""
    gauges = GaugeLengths.of(specimen)
    noisy = noisy_curve(curve, spec, gauges)
    window = measure.modulus_window
    exact = elastic_constants(first_loading(curve), window, measure.fit)
    measured = elastic_constants(first_loading(noisy), window, measure.fit)
    u = elastic_uncertainty(first_loading(noisy), window, spec, gauges)
    report = {"E": u.E.as_dict() if u.E else None, "nu": u.nu.as_dict() if u.nu else None,
              "reliability": u.reliability, "note": u.note,
              "noiseless": {"E": exact.E, "nu": exact.nu},
              "noise": {k: v for k, v in asdict(spec).items() if k != "name"},
              "units": {"E": "MPa", "nu": "1", "load_cell_std": "N", "load_cell_resolution": "N",
                        "extensometer_std": "mm", "extensometer_resolution": "mm"}}
    return noisy, measured, report


EFFECT = Effect(name="noise", keys=PARAM_KEYS, parse=parse, role="measure", build=build,
                models=(), doc="load-cell and extensometer noise and resolution; E and ν with intervals")
