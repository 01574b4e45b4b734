"""Virtual strain gauges on the thickness faces and the ASTM E1012 percent bending.

Two gauges face each other on the faces z = 0 and z = h of the gauge section (at the centre of the
width), at three planes along the axis as ASTM E1012 places them: the extensometer's centre x_c
and x_c ± 0.4 G (G its gauge length). Each is a short extensometer of base G/5 (its two marks
follow the material, vlab.measure.instruments), reading the axial strain of the face. For two
opposite gauges E1012's axial strain is a = (ε₁ + ε₂)/2 and the bending strain b = (ε₁ − ε₂)/2,
so the percent bending is

    B = b / a × 100 = (ε_top − ε_bottom) / (ε_top + ε_bottom) × 100

(signed: positive when the top face z = h stretches more). Reported at the last level whose
extensometer strain lies within the modulus window (where E is measured) and at the final level.
"""

from __future__ import annotations

import numpy as np

from vlab.geometry.specimen import GaugeMarks
from vlab.measure.instruments import extensometers

__all__ = ["FaceGauges", "percent_bending", "bending_report"]

PLANES = (-0.4, 0.0, 0.4)  # along the axis, in gauge lengths from the extensometer's centre
BASE = 0.2  # a strain gauge's base, in gauge lengths


def percent_bending(top: float, bottom: float) -> float | None:
    """(ε_top − ε_bottom) / (ε_top + ε_bottom) × 100; None at zero axial strain."""
    axial = top + bottom
    return None if axial == 0 else 100.0 * (top - bottom) / axial


class FaceGauges:
    """The six gauges (module docstring), read at every converged level."""

    def __init__(self, space, specimen):
        marks = specimen.extensometers[0]
        xc, G = 0.5 * (marks.a[0] + marks.b[0]), marks.length
        y, z0, z1 = specimen.thickness.a[1], specimen.thickness.a[2], specimen.thickness.b[2]
        self.x = [xc + p * G for p in PLANES]
        gauges = [GaugeMarks((x - BASE * G / 2, y, z), (x + BASE * G / 2, y, z)) for x in self.x for z in (z1, z0)]
        self.gauges = extensometers(space, gauges)
        self.rows: list[list[float]] = []

    def read(self, u: np.ndarray) -> None:
        self.rows.append([g.strain(u) for g in self.gauges])


def _level(gauges: FaceGauges, i: int, strain: float) -> dict:
    row = gauges.rows[i]
    planes = [{"x": x, "strain_top": row[2 * k], "strain_bottom": row[2 * k + 1],
               "percent_bending": percent_bending(row[2 * k], row[2 * k + 1])} for k, x in enumerate(gauges.x)]
    values = [abs(p["percent_bending"]) for p in planes if p["percent_bending"] is not None]
    return {"extensometer_strain": strain, "planes": planes, "percent_bending": planes[1]["percent_bending"],
            "max_percent_bending": max(values) if values else None}


def bending_report(gauges: FaceGauges, curve, window: tuple[float, float]) -> dict | None:
    """results.json → bending: the gauges at small strain (in the modulus window) and at the end."""
    if not gauges.rows:
        return None
    strain = np.abs(np.array(curve.strain[0]))
    small = np.flatnonzero((strain > 0) & (strain <= window[1] * (1 + 1e-9)))
    out = {"definition": "ASTM E1012, two opposite gauges: B = (e_top - e_bottom) / (e_top + e_bottom) x 100 %",
           "faces": "z = 0 (bottom) and z = thickness (top), at the width's centre",
           "gauge_base": BASE * float(np.ptp(gauges.x)) / (PLANES[2] - PLANES[0]),
           "final": _level(gauges, len(gauges.rows) - 1, curve.strain[0][-1])}
    if len(small):
        i = int(small[-1])
        out["small_strain"] = _level(gauges, i, curve.strain[0][i])
    return out
