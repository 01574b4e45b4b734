"""Why a measured constant differs from the input by design, next to the number.

Viscoelasticity (Prony series on the isochoric part, bulk modulus K not viscous): the shear
relaxation modulus is μ(t) = μ∞ (1 + Σ βᵢ exp(−t/τᵢ)) (MPa), μ∞ the ground law's. A ramp that
crosses the E-fit window at times t ∈ [t₁, t₂] (s after the start) measures, in the quasi-elastic
approximation, E(t̄) = 9 K μ(t̄) / (3 K + μ(t̄)) and ν(t̄) = (3 K − 2 μ(t̄)) / (2 (3 K + μ(t̄))) at the
window's mean time t̄ — between the long-term E∞ (the input) and the instantaneous E₀ = E(0).
"""

from __future__ import annotations

import numpy as np

from vlab.moduli import from_pair


def viscoelastic_apparent(data: dict) -> dict | None:
    """The rate-dependent moduli a viscoelastic test measures (None without the effect or time)."""
    visco = ((data.get("effects") or {}).get("declared") or {}).get("viscoelastic")
    fit = data["measured"].get("E_fit") or {}
    curve = data["curve"]
    window = fit.get("window") or (None, None)
    # a kind without an extensometer strain or a single E window (biaxial: one per axis) has no such note
    if not visco or not curve.get("time") or None in window or "strain" not in curve:
        return None
    strain, time = np.abs(np.asarray(curve["strain"], float)), np.asarray(curve["time"], float)
    lo, hi = fit["window"]
    first = np.flatnonzero(np.diff(strain) < 0)  # only the first loading ramp is fitted
    n = first[0] + 1 if first.size else len(strain)
    inside = (strain[:n] >= lo) & (strain[:n] <= hi)
    if not inside.any():
        return None
    t_mid = float(time[:n][inside].mean())
    inp = from_pair({"E": data["input"]["E"], "nu": data["input"]["nu"]})
    tau, beta = np.asarray(visco["tau"], float), np.asarray(visco["beta"], float)

    def at(t: float):
        return from_pair({"K": inp.K, "mu": inp.mu * (1.0 + float(np.sum(beta * np.exp(-t / tau))))})

    now, instant = at(t_mid), at(0.0)
    relaxed = float(np.sum(beta * (1.0 - np.exp(-t_mid / tau))) / max(np.sum(beta), 1e-300))
    return {"t_mid": t_mid, "relaxed": relaxed, "E": now.E, "nu": now.nu, "E_0": instant.E, "nu_0": instant.nu,
            "E_inf": inp.E, "nu_inf": inp.nu}


def by_design_notes(data: dict) -> dict[str, str]:
    """{'E': text, 'nu': text}: why each measured constant differs from its input, if it does by design."""
    app = viscoelastic_apparent(data)
    if app is None:
        return {}
    why = (f"rate-dependent: the ramp crosses the fit window at t ≈ {app['t_mid']:.3g} s, when the Prony "
           f"terms have relaxed {100 * app['relaxed']:.2g} % of their modulus")
    return {"E": f"{why}; expected ≈ {app['E']:.4g} MPa (quasi-elastic), between the long-term "
                 f"{app['E_inf']:.4g} (input) and the instantaneous {app['E_0']:.4g} MPa",
            "nu": f"{why}; expected ≈ {app['nu']:.4g}, between the long-term {app['nu_inf']:.4g} (input) "
                  f"and the instantaneous {app['nu_0']:.4g}"}
