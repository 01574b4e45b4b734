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
noiseless values measured from the exact curve. Uniaxial tests only report intervals. The measurement itself is vlab.measure.noise.measure_with_noise
(called by the run); this module is the grammar only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.effects.registry import Effect
from vlab.fields import SceneError, Table


@dataclass(frozen=True)
class NoiseSpec:
    """Instrument noise: standard deviations and resolutions (0 = none), the seed, the confidence."""

    load_cell_std: float = 0.0            # N
    load_cell_resolution: float = 0.0     # N
    extensometer_std: float = 0.0         # mm of elongation
    extensometer_resolution: float = 0.0  # mm
    seed: int = 0
    confidence: float = 0.95
    name: str = "noise"  # the effect's name in a scene's [effects]

    def strain_std(self, gauge_length: float) -> float:
        """Standard deviation of a strain reading over ``gauge_length`` mm (noise + rounding)."""
        return float(np.sqrt(self.extensometer_std**2 + self.extensometer_resolution**2 / 12.0)) / gauge_length



PARAM_KEYS = ("load_cell_std", "load_cell_resolution", "extensometer_std", "extensometer_resolution",
              "seed", "confidence")


def parse_params(raw: dict, prefix: str) -> NoiseSpec:
    """Build a NoiseSpec from ``[effects.noise]``.

    Keys (all optional, but at least one std or resolution must be > 0): load_cell_std ≥ 0 N,
    load_cell_resolution ≥ 0 N, extensometer_std ≥ 0 mm, extensometer_resolution ≥ 0 mm,
    seed integer 0..2⁶³−1 (default 0), confidence in [0.5, 1) (default 0.95).
    """
    t = Table(prefix, raw, PARAM_KEYS)
    spec = NoiseSpec(
        load_cell_std=t.number("load_cell_std", 0.0, ge=0.0, note=" (N, standard deviation)"),
        load_cell_resolution=t.number("load_cell_resolution", 0.0, ge=0.0, note=" (N, reading step; 0 = none)"),
        extensometer_std=t.number("extensometer_std", 0.0, ge=0.0, note=" (mm of elongation, standard deviation)"),
        extensometer_resolution=t.number("extensometer_resolution", 0.0, ge=0.0,
                                         note=" (mm, reading step; 0 = none)"),
        seed=t.integer("seed", 0, 2**63 - 1, default=0),
        confidence=t.number("confidence", 0.95, ge=0.5, lt=1.0, note=" (e.g. 0.68 or 0.95)"),
    )
    if not any((spec.load_cell_std, spec.load_cell_resolution, spec.extensometer_std,
                spec.extensometer_resolution)):
        raise ValueError(f"[{prefix}] sets no noise: give load_cell_std, load_cell_resolution, "
                         "extensometer_std or extensometer_resolution > 0 (or drop the section)")
    return spec


def parse(t, material, test) -> NoiseSpec:
    try:
        return parse_params(t.raw, "effects.noise")
    except ValueError as exc:
        raise SceneError(str(exc)) from None


def build(spec: NoiseSpec) -> NoiseSpec:
    return spec


EFFECT = Effect(name="noise", keys=PARAM_KEYS, parse=parse, role="measure", build=build,
                models=(), doc="load-cell and extensometer noise and resolution; E and ν with intervals")
