"""Virtual strain gauges on the four faces and the ASTM E1012 percent bending.

Four gauges at each of three planes along the axis, as ASTM E1012 places them: the extensometer's
centre x_c and x_c ± 0.4 G (G its gauge length). Two face each other on the thickness faces z = 0
and z = h (at the centre of the width), two on the width faces y = y₀ and y = y₁ (at
mid-thickness). Each is a short extensometer of base G/5 (its two marks follow the material,
vlab.measure.instruments), reading the axial strain of the face.

E1012 splits the four readings into the axial strain and the bending strain of each pair of
opposite gauges:

    a = (ε_top + ε_bottom + ε_y₁ + ε_y₀) / 4,   b_z = (ε_top − ε_bottom)/2,   b_y = (ε_y₁ − ε_y₀)/2

and the four-gauge percent bending is the bending strain's magnitude over the axial strain,

    B = √(b_y² + b_z²) / a × 100

(E1012's four-sensor formula, as MTS's 709 alignment system implements it: B = ½√((b₁ − b₃)² +
(b₂ − b₄)²) with b_i = ε_i − a, the same number). Each plane also gives the two-gauge values of
its pairs, signed, B_z = (ε_top − ε_bottom)/(ε_top + ε_bottom) × 100 (positive when z = h
stretches more) and B_y = (ε_y₁ − ε_y₀)/(ε_y₁ + ε_y₀) × 100, and the bending of the rectangle's
most strained corner fibre in beam theory, (|b_y| + |b_z|)/a × 100. Reported at the last level
whose extensometer strain lies within the modulus window (where E is measured) and at the final
level.
"""

from __future__ import annotations

import math

import numpy as np

from vlab.geometry.specimen import GaugeMarks
from vlab.measure.instruments import extensometers

__all__ = ["FaceGauges", "percent_bending", "four_gauge_bending", "bending_report"]

PLANES = (-0.4, 0.0, 0.4)  # along the axis, in gauge lengths from the extensometer's centre
BASE = 0.2  # a strain gauge's base, in gauge lengths
FACES = ("top", "bottom", "y1", "y0")  # z = h, z = 0, y = y₁, y = y₀: the gauges' order in a plane


def percent_bending(first: float, second: float) -> float | None:
    """Two opposite gauges: (ε₁ − ε₂) / (ε₁ + ε₂) × 100; None at zero axial strain."""
    axial = first + second
    return None if axial == 0 else 100.0 * (first - second) / axial


def four_gauge_bending(top: float, bottom: float, y1: float, y0: float) -> tuple[float | None, float | None]:
    """(B, the corner fibre's bending) of four gauges: √(b_y² + b_z²)/a × 100 and
    (|b_y| + |b_z|)/a × 100 (module docstring); None at zero axial strain."""
    a = (top + bottom + y1 + y0) / 4.0
    if a == 0:
        return None, None
    b_z, b_y = (top - bottom) / 2.0, (y1 - y0) / 2.0
    return 100.0 * math.hypot(b_y, b_z) / abs(a), 100.0 * (abs(b_y) + abs(b_z)) / abs(a)


class FaceGauges:
    """The twelve gauges (module docstring), read at every converged level."""

    def __init__(self, space, specimen):
        marks = specimen.extensometers[0]
        xc, G = 0.5 * (marks.a[0] + marks.b[0]), marks.length
        y_mid, z0, z1 = specimen.thickness.a[1], specimen.thickness.a[2], specimen.thickness.b[2]
        y0, y1, z_mid = specimen.transverse[0].a[1], specimen.transverse[0].b[1], specimen.transverse[0].a[2]
        self.x = [xc + p * G for p in PLANES]
        spots = ((y_mid, z1), (y_mid, z0), (y1, z_mid), (y0, z_mid))  # in FACES' order
        gauges = [GaugeMarks((x - BASE * G / 2, y, z), (x + BASE * G / 2, y, z)) for x in self.x for y, z in spots]
        self.gauges = extensometers(space, gauges)
        self.rows: list[list[float]] = []

    def read(self, u: np.ndarray) -> None:
        self.rows.append([g.strain(u) for g in self.gauges])


def _plane(x: float, strains: list[float]) -> dict:
    e = dict(zip(FACES, strains))
    B, corner = four_gauge_bending(e["top"], e["bottom"], e["y1"], e["y0"])
    return {"x": x, **{f"strain_{k}": v for k, v in e.items()},
            "percent_bending_thickness": percent_bending(e["top"], e["bottom"]),
            "percent_bending_width": percent_bending(e["y1"], e["y0"]),
            "percent_bending": B, "corner_percent_bending": corner}


def _level(gauges: FaceGauges, i: int, strain: float) -> dict:
    row, n = gauges.rows[i], len(FACES)
    planes = [_plane(x, row[n * k:n * (k + 1)]) for k, x in enumerate(gauges.x)]
    values = [p["percent_bending"] for p in planes if p["percent_bending"] is not None]
    return {"extensometer_strain": strain, "planes": planes, "percent_bending": planes[1]["percent_bending"],
            "percent_bending_thickness": planes[1]["percent_bending_thickness"],
            "percent_bending_width": planes[1]["percent_bending_width"],
            "max_percent_bending": max(values) if values else None}


def bending_report(gauges: FaceGauges, curve, window: tuple[float, float]) -> dict | None:
    """results.json → bending: the gauges at small strain (in the modulus window) and at the end."""
    if not gauges.rows:
        return None
    strain = np.abs(np.array(curve.strain[0]))
    small = np.flatnonzero((strain > 0) & (strain <= window[1] * (1 + 1e-9)))
    out = {"definition": "ASTM E1012, four gauges: a = mean, b_z = (e_top - e_bottom)/2, b_y = (e_y1 - e_y0)/2, "
                         "B = sqrt(b_y^2 + b_z^2) / a x 100 %; per pair (e1 - e2)/(e1 + e2) x 100 %, signed",
           "faces": "z = 0 (bottom) and z = thickness (top) at the width's centre; y = y0 and y = y1 (the width "
                    "faces) at mid-thickness",
           "gauge_base": BASE * float(np.ptp(gauges.x)) / (PLANES[2] - PLANES[0]),
           "final": _level(gauges, len(gauges.rows) - 1, curve.strain[0][-1])}
    if len(small):
        i = int(small[-1])
        out["small_strain"] = _level(gauges, i, curve.strain[0][i])
    return out
