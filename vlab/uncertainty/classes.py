"""Instrument classes and specimen dimension tolerances, with their sources.

Load cell, ISO 7500-1:2018 Table 2 (force-measuring system of a testing machine), per class:
relative accuracy error q (%), relative resolution a (%). Class 1 is what ISO 527-1:2019 §5.1.4
requires for plastics.

    class   q      a
    0.5     0.5    0.25
    1       1.0    0.5
    2       2.0    1.0
    3       3.0    1.5

Extensometer, ISO 9513:2012 Table 2, per class: gauge-length relative error q_Le (%), resolution
(% of the reading or µm, the greater), bias (% of the reading or µm, the greater). ISO 527-1
§5.1.5.1 requires class 1 for the modulus. (Checked for class 0.5 against a manufacturer's
calibration note, http://laserextensometer.net/en/products/lex/calib05.html: ±0.5 % of the
reading, ±1.5 µm below 300 µm.)

    class   q_Le   resolution % / µm   bias % / µm
    0.2     0.2    0.1  / 0.2          0.2 / 0.6
    0.5     0.5    0.25 / 0.5          0.5 / 1.5
    1       1.0    0.5  / 1.0          1.0 / 3.0
    2       2.0    1.0  / 2.0          2.0 / 6.0

How the classes enter a virtual test (vlab.uncertainty.model): the class limit of a relative
error is the half-width of a rectangular distribution (GUM 4.3.7: u = q/√3); the readings are
quantised at the resolution; the absolute bias is a constant offset of the elongation, which the
slope of a modulus fit does not see, so only its relative part is drawn.

Dimension tolerances (mm, ± half-width), from the standards' tables as quoted in the shipped
dimension files (vlab/data/standards/*.toml) and, for ASTM D638, the table reproduced at
http://kcafrp.com/sub06/01_01_2.php. A standard that gives no tolerance for a dimension (ISO 527-2
1BA thickness: h ≥ 2 only; ASTM D638 IV thickness; ASTM D412 C width and bench marks) has none
here: give it in the scene's [uncertainty] table.
"""

from __future__ import annotations

__all__ = ["LOAD_CELL", "EXTENSOMETER", "TOLERANCES", "standard_tolerances"]

#: ISO 7500-1 class -> {"q": relative accuracy error, "a": relative resolution} (fractions)
LOAD_CELL = {0.5: {"q": 0.005, "a": 0.0025}, 1.0: {"q": 0.01, "a": 0.005},
             2.0: {"q": 0.02, "a": 0.01}, 3.0: {"q": 0.03, "a": 0.015}}

#: ISO 9513 class -> gauge-length error q_Le, resolution (relative, mm), bias (relative, mm)
EXTENSOMETER = {
    0.2: {"q_Le": 0.002, "res_rel": 0.001, "res_abs": 0.0002, "bias_rel": 0.002, "bias_abs": 0.0006},
    0.5: {"q_Le": 0.005, "res_rel": 0.0025, "res_abs": 0.0005, "bias_rel": 0.005, "bias_abs": 0.0015},
    1.0: {"q_Le": 0.01, "res_rel": 0.005, "res_abs": 0.001, "bias_rel": 0.01, "bias_abs": 0.003},
    2.0: {"q_Le": 0.02, "res_rel": 0.01, "res_abs": 0.002, "bias_rel": 0.02, "bias_abs": 0.006},
}

#: standard name -> {dimension: tolerance (mm, ± half-width)}
TOLERANCES = {
    "ISO 527-2 1A": {"width": 0.2, "thickness": 0.2, "gauge_length": 0.5},
    "ISO 527-2 1BA": {"width": 0.5, "gauge_length": 0.5},
    "ISO 37 2": {"width": 0.1, "thickness": 0.2, "gauge_length": 0.5},
    "ASTM D638 IV": {"width": 0.5, "gauge_length": 0.13},
    "ASTM D412 C": {"thickness": 0.2},
}


def standard_tolerances(standard: str) -> dict[str, float]:
    """The dimension tolerances of a shipped standard (case- and space-insensitive name), or {}."""
    key = "".join(standard.lower().split())
    for name, tol in TOLERANCES.items():
        if "".join(name.lower().split()) == key:
            return dict(tol)
    return {}
