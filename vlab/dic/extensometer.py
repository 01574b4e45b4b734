"""The DIC virtual extensometer: the axial and transverse strain of the gauge area from the DIC
strain maps, for the same E and ν fits as the point extensometers (vlab.measure.elastic_constants).

Gauge area: on the face, between the axial gauge marks along the loading axis (mesh x) and, across
it, between the transverse marks where they lie along the face's other axis (else the face's
extent there), where the DIC converged; the run's region of interest keeps every subset wholly
on the specimen (vlab.dic.instrument.region_of_interest) and the strain window fits one-sided
planes at the edges, so no point of the area sees past the specimen's edge. The strain of a level is the mean over the converged points of the area of the
engineering strain of a fibre along the axis, from the Green–Lagrange component E_aa,

    ε_a = √(1 + 2 E_aa) − 1                      (a fibre's stretch λ_a = √C_aa, C = I + 2E),

the same measure as the point extensometer's (ℓ − L)/L in a homogeneous gauge section.
"""

from __future__ import annotations

import numpy as np

from vlab.dic import icgn

LOADING_AXIS = 0  # mesh x: every uniaxial specimen is pulled along x


def image_axes(view) -> tuple[str, str] | None:
    """(axial, transverse) strain component names of the image ("exx"/"eyy"), or None when the
    loading axis is normal to the face (the camera cannot see the axial strain)."""
    along = [a for a, _ in view.face.axes]
    if along[0] == LOADING_AXIS:
        return "exx", "eyy"
    if along[1] == LOADING_AXIS:
        return "eyy", "exx"
    return None


def gauge_area(view, specimen, field) -> np.ndarray:
    """The grid points (rows, cols) bool of the gauge area (module docstring)."""
    face, axes = view.face, view.face.axes
    x1, x2 = view.face_mm(field.x, field.y)
    coords = (x1, x2)
    k_axial = 0 if axes[0][0] == LOADING_AXIS else 1
    k_across = 1 - k_axial
    marks = specimen.extensometers[LOADING_AXIS]
    lo_hi = [axes[k_axial][1] * np.array([marks.a[LOADING_AXIS], marks.b[LOADING_AXIS]])]
    across_axis, sign = axes[k_across]
    transverse = specimen.transverse.get(LOADING_AXIS)
    if transverse is not None and abs(transverse.a[across_axis] - transverse.b[across_axis]) > 0:
        lo_hi.append(sign * np.array([transverse.a[across_axis], transverse.b[across_axis]]))
    else:
        lo, hi = face.bounds
        lo_hi.append(np.array([lo[k_across], hi[k_across]]))
    axial, across = (np.sort(v) for v in lo_hi)
    inside = (coords[k_axial] >= axial[0]) & (coords[k_axial] <= axial[1])
    inside &= (coords[k_across] >= across[0]) & (coords[k_across] <= across[1])
    return inside & (field.status == icgn.OK)


def fibre_strain(E: np.ndarray) -> np.ndarray:
    """ε = √(1 + 2E) − 1 of a Green–Lagrange normal component E."""
    return np.sqrt(1.0 + 2.0 * E) - 1.0


def gauge_strains(view, specimen, fields) -> dict:
    """Per level the mean axial and transverse engineering strain over the gauge area, and the
    number of points averaged; None (with a reason) when the face cannot show the axial strain."""
    names = image_axes(view)
    if names is None:
        return {"note": f"the loading axis x is normal to the {view.name} face: no axial strain to see"}
    axial, across, points = [], [], []
    for f in fields:
        area = gauge_area(view, specimen, f)
        a, t = fibre_strain(getattr(f, names[0])[area]), fibre_strain(getattr(f, names[1])[area])
        ok = np.isfinite(a) & np.isfinite(t)
        points.append(int(ok.sum()))
        axial.append(float(a[ok].mean()) if ok.any() else float("nan"))
        across.append(float(t[ok].mean()) if ok.any() else float("nan"))
    return {"axial": axial, "transverse": across, "points": points, "components": list(names)}
