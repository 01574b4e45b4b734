"""The spatial resolution of a run's own camera, pattern and DIC settings, and its Metrological
Efficiency Indicator (DIC Challenge 2.0: P. L. Reu et al., "DIC Challenge 2.0: Developing Images
and Guidelines for Evaluating Accuracy and Resolution of 2D Analyses. Focus on the Metrological
Efficiency Indicator", Experimental Mechanics 62 (2022) 639–654, doi:10.1007/s11340-021-00806-6).

Spatial resolution SR: the period T (px) of a sinusoidal displacement at which the measured
amplitude is 10 % low. The face is moved by n = A sin(2π s / T), A = 0.5 px, along the image axis
s of the region of interest's longer extent (s = x: v = A sin(2π x / T), the face moving along −e₂;
s = y: u = A sin(2π y / T), along e₁). The image is the camera's: the speckle painted on the face,
each pixel's s × s sub-samples mapped back exactly through the analytic inverse of the sinusoid
(vlab.dic.camera.irradiance_mapped; the FE mesh cannot carry a field of a few subsets' period),
then the camera's exposure (blur, a fresh draw of the sensor noise, rounding to its bit depth).
It is correlated against the run's reference image with the run's settings over the run's region
of interest, and vlab.dic.metrics.sinusoid_ratios gives the displacement and strain
(E_xy = ½ ∂n/∂s, amplitude π A / T) amplitude ratios. The periods sweep T_k = 2.5 h · 1.25^k (h the
subset) until both ratios have risen through 0.9 or T passes the region's extent along s (then
"not reached"); SR is the log-linear crossing (vlab.dic.metrics.crossing).

The closed form to compare with (Reu et al. 2022, appendix): on noise-free images local DIC with
an affine subset of h px returns the least-squares affine fit of the field over the subset, whose
value at the centre is the subset's box average, so the displacement ratio is the Dirichlet kernel

    r_u(T) = sin(π h / T) / (h sin(π / T)),   10 % low at T ≈ 3.99 h

(67.8 px for h = 17, the paper's theoretical value); the strain window (a least-squares slope over
w grid points at step p) multiplies it by Σ_k c_k sin(ω k p) / ω, c_k = k p / Σ_j (j p)², ω = 2π/T.

MEI (vlab.dic.metrics.mei): MEI_u = σ_n · SR_u (px²), MEI_ε = σ_Exy · SR_ε² (px²), σ the static
pair's noise of the moved component and of E_xy.
"""

from __future__ import annotations

import time

import numpy as np

AMPLITUDE_PX = 0.5
START = 2.5  # first period, in subsets: well below the displacement's 10 % crossing (≈ 3.99 subsets)
RATIO = 1.25  # between periods: on the closed-form curves the log-linear crossing lands 0.4 % (u), 0.2–1.1 % (ε) high
LEVEL = 0.9  # measured amplitude 10 % low
FRAMES = 2_000_000  # frame indices of the sinusoid images (fresh noise, never a level's or the static pair's)


def box_ratio(subset: int, period):
    """r_u(T) = sin(π h / T) / (h sin(π / T)): an affine subset's displacement amplitude ratio."""
    period = np.asarray(period, float)
    return np.sin(np.pi * subset / period) / (subset * np.sin(np.pi / period))


def window_ratio(subset: int, step: int, window: int, period):
    """r_ε(T) = r_u(T) · Σ_k c_k sin(ω k p) / ω: the strain window's least-squares slope of the
    subset-averaged displacement, over the true slope."""
    omega = 2 * np.pi / np.asarray(period, float)
    k = (np.arange(window) - (window - 1) / 2) * step
    c = k / np.sum(k * k)
    slope = np.sum(c * np.sin(np.multiply.outer(omega, k)), axis=-1) / omega
    return box_ratio(subset, period) * slope


def theory(settings) -> dict:
    """The closed-form SR_u and SR_ε (px) of ``settings`` (subset, step, strain_window)."""
    from scipy.optimize import brentq

    h = settings.subset
    return {"displacement_px": float(brentq(lambda T: box_ratio(h, T) - LEVEL, 1.5 * h, 100 * h)),
            "strain_px": float(brentq(lambda T: window_ratio(h, settings.step, settings.strain_window, T) - LEVEL,
                                      1.5 * h, 100 * h))}


def _inverse(view, along: int, period: float, amplitude: float):
    """(x₁, x₂) ↦ (X₁, X₂) mm of the sinusoid along image axis ``along``: pixel column
    j = (x₁ − c₁)/p + (W − 1)/2, row i = (c₂ − x₂)/p + (H − 1)/2 (vlab.dic.camera)."""
    (W, H), p = view.camera.pixels, view.camera.pitch
    c = view.camera.centre_on(view.face)
    k = 2 * np.pi / period
    if along == 0:  # v = A sin(k j) px down the image: x₂ = X₂ − p v
        return lambda x1, x2: (x1, x2 + p * amplitude * np.sin(k * ((x1 - c[0]) / p + (W - 1) / 2)))
    return lambda x1, x2: (x1 - p * amplitude * np.sin(k * ((c[1] - x2) / p + (H - 1) / 2)), x2)


def _extent(correlator) -> tuple[int, float]:
    """The image axis along which the region of interest's subset centres spread further, and
    that spread plus one subset (px): the longest period the region holds once."""
    cx, cy = correlator.cx[correlator.active], correlator.cy[correlator.active]
    if cx.size == 0:
        return 0, 0.0
    spans = (np.ptp(cx), np.ptp(cy))
    along = int(spans[1] > spans[0])
    return along, float(spans[along] + correlator.settings.subset)


def _ratios(view, pattern, correlator, along: int, period: float, frame: int) -> dict:
    from vlab.dic.camera import expose, irradiance_mapped
    from vlab.dic.metrics import sinusoid_ratios

    image = expose(view.camera, irradiance_mapped(view.camera, view.face, pattern,
                                                  _inverse(view, along, period, AMPLITUDE_PX)), frame)
    f = correlator.correlate(image.astype(float))
    ru, re = sinusoid_ratios(f, period, AMPLITUDE_PX, view.settings.strain_window, along)
    return {"period_px": float(period), "displacement_ratio": ru, "strain_ratio": re, "converged": f.converged}


def spatial_resolution(view, pattern, correlator) -> dict:
    """SR_u and SR_ε (px and mm) of the run's camera (module docstring): ``pattern`` the painted
    speckle, ``correlator`` the run's (reference image, settings, region of interest). Also the
    sweep's rows, the closed-form values, the axis and the time taken (s)."""
    from vlab.dic.metrics import crossing

    start = time.perf_counter()
    along, longest = _extent(correlator)
    rows, period = [], START * view.settings.subset
    while period <= longest:
        rows.append(_ratios(view, pattern, correlator, along, period, FRAMES + len(rows)))
        if all(_crossed(rows, key) for key in ("displacement_ratio", "strain_ratio")):
            break
        period *= RATIO
    periods, p = [r["period_px"] for r in rows], view.camera.pitch
    out = {"component": "v" if along == 0 else "u", "along": "xy"[along], "amplitude_px": AMPLITUDE_PX,
           "longest_period_px": longest, "rows": rows, "theory": theory(view.settings)}
    for name, key in (("displacement", "displacement_ratio"), ("strain", "strain_ratio")):
        sr = crossing(periods, [r[key] for r in rows], LEVEL)
        out[f"{name}_px"], out[f"{name}_mm"] = sr, None if sr is None else sr * p
    out["time_s"] = time.perf_counter() - start
    return out


def _crossed(rows: list[dict], key: str) -> bool:
    values = [r[key] for r in rows]
    return any(a < LEVEL <= b for a, b in zip(values, values[1:]))
