"""The error metrics DIC users report (DIC Challenge 2.0, Reu et al. 2022, Exp. Mech. 62:639),
measured on images rendered exactly from known fields (vlab.dic.speckle):

- displacement noise floor σ_u (px): the standard deviation of u and v between two images of the
  same, static pattern with independent grey-level noise;
- strain noise σ_ε (µε): the standard deviation of E_xx, E_yy, E_xy over the same static pair;
- bias on rigid sub-pixel translations 0.1 … 0.9 px: the worst |mean error| (px);
- spatial resolution (px): the period T of a sinusoidal displacement v = A sin(2π x / T) at which
  the measured amplitude (least-squares sinusoid through the converged subsets) is 10 % low;
  for strain, the same on E_xy = ½ ∂v/∂x = (π A / T) cos(2π x / T) where the whole strain
  window converged;
- Metrological Efficiency Indicator (Reu et al. 2022, after Blaysat, Grédiac & Sur): noise times
  spatial resolution, MEI_u = σ_u · SR_u (px²) and MEI_ε = σ_ε · SR_ε² (px²), the powers that
  make it independent of the subset and strain window chosen (σ_u falls as 1/h with the subset
  side h, σ_ε as 1/h² with the subset and window together); smaller is better, and it is a
  property of the algorithm and the images (pattern, noise), not of the settings.

vlab.dic.resolution measures the same on a run's own camera (vlab.dic.instrument).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.dic import icgn, speckle
from vlab.dic.correlate import Correlator, Settings


@dataclass(frozen=True)
class Camera:
    """What the test images look like: shape, speckle, noise (share of the full scale), pixel
    supersampling of the renderer."""

    shape: tuple[int, int] = (256, 256)
    speckle_size: float = 4.0
    density: float = 0.5
    seed: int = 0
    noise: float = 0.01
    supersample: int = 3


def _image(camera, pattern, shape, inverse=None, noise_seed=None):
    image = speckle.render(pattern, shape, inverse, camera.supersample)
    return speckle.add_noise(image, camera.noise, noise_seed) if camera.noise and noise_seed is not None else image


def noise_floor(settings: Settings, camera: Camera) -> dict:
    """σ_u, σ_v (px) and σ_Exx, σ_Eyy (µε) from a static pair with independent noise."""
    pattern = speckle.make_pattern(camera.shape, camera.speckle_size, camera.density, camera.seed)
    clean = speckle.render(pattern, camera.shape, None, camera.supersample)
    a = speckle.add_noise(clean, camera.noise, 1)
    b = speckle.add_noise(clean, camera.noise, 2)
    return static_noise(Correlator(a, settings).correlate(b))


def static_noise(f) -> dict:
    """σ_u, σ_v (px) and σ_Exx, σ_Eyy, σ_Exy (µε): the standard deviations over the converged subsets of
    the field ``f`` of a static pair (two images of one state, independent noise)."""
    ok = f.status == icgn.OK
    if not ok.any():
        return {"sigma_u_px": None, "sigma_v_px": None, "sigma_exx_microstrain": None,
                "sigma_eyy_microstrain": None, "sigma_exy_microstrain": None, "converged": f.converged}
    return {"sigma_u_px": float(np.std(f.u[ok])), "sigma_v_px": float(np.std(f.v[ok])),
            "sigma_exx_microstrain": float(np.nanstd(f.exx) * 1e6),
            "sigma_eyy_microstrain": float(np.nanstd(f.eyy) * 1e6),
            "sigma_exy_microstrain": float(np.nanstd(f.exy) * 1e6), "converged": f.converged}


def translation_bias(settings: Settings, camera: Camera, shifts=np.arange(1, 10) / 10) -> dict:
    """Per shift (in x and y alike): mean error and standard deviation (px)."""
    pattern = speckle.make_pattern(camera.shape, camera.speckle_size, camera.density, camera.seed)
    ref = _image(camera, pattern, camera.shape, None, 1)
    c = Correlator(ref, settings)
    rows = []
    for k, t in enumerate(shifts):
        f = c.correlate(_image(camera, pattern, camera.shape, speckle.translation(t, t), 10 + k))
        ok = f.status == icgn.OK
        eu, ev = f.u[ok] - t, f.v[ok] - t
        rows.append({"shift_px": float(t), "bias_u_px": float(eu.mean()), "bias_v_px": float(ev.mean()),
                     "std_u_px": float(eu.std()), "std_v_px": float(ev.std()), "converged": f.converged})
    return {"rows": rows, "worst_bias_px": max(max(abs(r["bias_u_px"]), abs(r["bias_v_px"])) for r in rows),
            "worst_std_px": max(max(r["std_u_px"], r["std_v_px"]) for r in rows)}


def sine_amplitude(x: np.ndarray, values: np.ndarray, period: float) -> float:
    """The amplitude of the least-squares a sin(kx) + b cos(kx) + c through (x, values)."""
    k = 2 * np.pi / period
    A = np.stack([np.sin(k * x), np.cos(k * x), np.ones_like(x)], axis=1)
    (a, b, _), *_ = np.linalg.lstsq(A, values, rcond=None)
    return float(np.hypot(a, b))


def crossing(periods, ratios, level=0.9) -> float | None:
    """The period where the ratio first rises through ``level`` (linear in log period)."""
    for (t0, r0), (t1, r1) in zip(zip(periods, ratios), zip(periods[1:], ratios[1:])):
        if r0 < level <= r1:
            w = (level - r0) / (r1 - r0)
            return float(np.exp(np.log(t0) + w * (np.log(t1) - np.log(t0))))
    return None


def sinusoid_ratios(f, period: float, amplitude: float, window: int, along: int = 0) -> tuple[float, float]:
    """(displacement, strain) amplitude ratios, measured / true, of the field ``f`` of the sinusoid
    n = A sin(2π s / T) along image axis ``along`` (0: s = x, n = v; 1: s = y, n = u): the
    least-squares amplitude (sine_amplitude) of n through the converged subsets over A, and that of
    E_xy = ½ ∂n/∂s (amplitude π A / T) over π A / T through the grid points whose whole
    ``window`` × ``window`` strain window converged (a window truncated by the region's edge or a
    failed subset is a different, one-sided filter)."""
    from scipy.ndimage import binary_erosion

    ok = f.status == icgn.OK
    s, n = (f.x, f.v) if along == 0 else (f.y, f.u)
    full = binary_erosion(ok, np.ones((window, window), bool), border_value=0) & np.isfinite(f.exy)
    if ok.sum() < 4 or full.sum() < 4:
        return float("nan"), float("nan")
    ru = sine_amplitude(s[ok].astype(float), n[ok], period) / amplitude
    re = sine_amplitude(s[full].astype(float), f.exy[full], period) / (np.pi * amplitude / period)
    return ru, re


def spatial_resolution(settings: Settings, camera: Camera, periods, amplitude: float = 0.5) -> dict:
    """Displacement and strain amplitude ratios (measured / true) per period of v = A sin(2πx/T),
    on noise-free images of ``camera.shape``, and the periods where they are 10 % low."""
    pattern = speckle.make_pattern(camera.shape, camera.speckle_size, camera.density, camera.seed)
    ref = speckle.render(pattern, camera.shape, None, camera.supersample)
    c = Correlator(ref, settings)
    rows = []
    for T in periods:
        f = c.correlate(speckle.render(pattern, camera.shape, speckle.sinusoid(amplitude, T), camera.supersample))
        ru, re = sinusoid_ratios(f, T, amplitude, settings.strain_window)
        rows.append({"period_px": float(T), "displacement_ratio": ru, "strain_ratio": re, "converged": f.converged})
    periods = [r["period_px"] for r in rows]
    return {"rows": rows, "component": "v",
            "displacement_px": crossing(periods, [r["displacement_ratio"] for r in rows]),
            "strain_px": crossing(periods, [r["strain_ratio"] for r in rows])}


def mei(noise: dict, resolution: dict) -> dict:
    """The Metrological Efficiency Indicator (DIC Challenge 2.0, Reu et al. 2022,
    doi:10.1007/s11340-021-00806-6): noise times spatial resolution, to the power that makes it
    nearly independent of the subset and window a user picks, MEI_u = σ_n · SR_u (px²) and, since
    strain noise falls as the square of the strain's resolution, the strain's noise times its
    squared resolution, MEI_ε = σ_Exy · SR_ε² (px²; σ_Exy as a strain, not µε).
    σ_n is the static pair's noise of the component the sinusoid moves (resolution["component"]:
    "u" or "v") and σ_Exy that of the strain measured on it, so each product pairs a noise with
    the resolution of the same quantity. Smaller is better; None where a resolution or noise is."""
    sn = noise.get(f"sigma_{resolution.get('component', 'v')}_px")
    se = noise.get("sigma_exy_microstrain")
    du, de = resolution["displacement_px"], resolution["strain_px"]
    return {"displacement_px2": None if du is None or sn is None else sn * du,
            "strain_px2": None if de is None or se is None else se * 1e-6 * de ** 2}
