"""Why a measured constant differs from the input by design, next to the number.

Nonlinear elasticity: E is the slope of a straight line (regression or chord, ``[measure] method``)
through the recorded points of the first loading with |ε| in the modulus window (vlab.measure.fit);
a hyperelastic stress–strain curve s(ε) bends there, so the slope is the curve's mean tangent over
the window, E_window ≈ ds/dε at the window's mean strain, and equals the input E (= ds/dε at ε = 0,
the small-strain limit) only for a straight curve. Where the scene has a closed-form homogeneous
state (``reference``: the roller block), the same line through the closed form's nominal stress P
at the same grip strains λ − 1 gives E_window without any FE: the FE's E equals it to its
discretisation error, which is what the accuracy estimate measures (zero for the homogeneous block).

Viscoelasticity (Prony series on the isochoric part, bulk modulus K not viscous): the shear
relaxation modulus is μ(t) = μ∞ (1 + Σ βᵢ exp(−t/τᵢ)) (MPa), μ∞ the ground law's. A ramp that
crosses the E-fit window at times t ∈ [t₁, t₂] (s after the start) measures, in the quasi-elastic
approximation, E(t̄) = 9 K μ(t̄) / (3 K + μ(t̄)) and ν(t̄) = (3 K − 2 μ(t̄)) / (2 (3 K + μ(t̄))) at the
window's mean time t̄ — between the long-term E∞ (the input) and the instantaneous E₀ = E(0).
"""

from __future__ import annotations

import numpy as np

from vlab.moduli import from_pair


def _first_loading(strain) -> int:
    """Readings of the first loading ramp (up to the first fall of |strain|): where E is fitted."""
    falls = np.flatnonzero(np.diff(np.abs(np.asarray(strain, float))) < 0)
    return int(falls[0]) + 1 if falls.size else len(strain)


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
    n = _first_loading(strain)
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


NONLINEAR_TOLERANCE = 1e-6  # |E − E_input| / E_input below this: the curve is straight in the window


def closed_form_slope(data: dict) -> float | None:
    """E_window of the closed-form homogeneous curve (MPa): the measurement's line (same window,
    same method) through P(λ) at the recorded grip strains λ − 1 of the first loading; None where
    the scene has no closed form or the kind has no single uniaxial E."""
    from vlab.measure.fit import FitError, fit_line

    ref = (data.get("reference") or {}).get("stress_x")
    fit = data["measured"].get("E_fit") or {}
    curve = data["curve"]
    if not ref or "strain_y" in curve or "stretch" not in curve or not fit.get("window"):
        return None
    strain = np.asarray(curve["stretch"][: len(ref)], float) - 1.0
    n = _first_loading(strain)
    try:
        line = fit_line(strain[:n], np.asarray(ref[:n], float), tuple(fit["window"]), fit.get("method", "regression"))
    except FitError:
        return None
    return line.slope


def _bends(name) -> bool:
    """Whether the model is a continuum law whose small-strain tangent is the input E and whose
    curve bends: not linear elasticity (straight), not a body such as the spring network (its E
    is the network's, vlab.materials.registry: ``continuum``)."""
    from vlab.materials.registry import MODELS

    entry = MODELS.get(name)
    return entry is not None and entry.continuum and name != "linear"


def nonlinear_note(data: dict, brief: bool = False) -> str | None:
    """Why E over the window differs from the input E of a nonlinear elastic model (module
    docstring), with the closed-form E_window where the scene has one; None where E equals the
    input (a straight curve) or is not measured. ``brief``: the console's one line."""
    m, inp = data["measured"], data["input"]
    fit = m.get("E_fit") or {}
    window = fit.get("window") or (None, None)
    if m.get("E") is None or None in window or not _bends(inp.get("model")) or not inp.get("E"):
        return None  # a kind without one E window (biaxial: one per axis) has no such note
    gap = abs(m["E"] - inp["E"])
    if gap <= NONLINEAR_TOLERANCE * abs(inp["E"]):
        return None
    lo, hi = fit["window"]
    exact = closed_form_slope(data)
    declared = (data.get("effects") or {}).get("declared") or {}
    model = " + ".join([inp.get("label", inp["model"]), *declared])  # the curve is the whole material's
    if brief:
        return (f"the slope of the {model} curve over |ε| {lo:g}–{hi:g}, not its tangent at ε = 0 (the input)"
                + (f"; closed form over the same points: {exact:.6g} MPa" if exact is not None else ""))
    line = "the chord" if fit.get("method") == "chord" else "the regression line"
    text = (f"E is the slope of {line} through the stress–strain points with |ε| in {lo:g}–{hi:g}; the "
            f"{model} curve bends there (its tangent is the input E only at ε = 0)")
    if exact is None:
        return text + (", so even an exact solution reads a slope other than the input; the FE's own error "
                       "is the accuracy estimate's")
    text += f". The closed-form homogeneous curve gives {exact:.6g} MPa over the same points"
    if abs(m["E"] - exact) <= 0.01 * gap:  # the FE adds nothing visible (the mesh's error: the estimate)
        text += ": the difference from the input is the material's, not the mesh's (that is the accuracy estimate)"
    return text


def by_design_notes(data: dict, brief: bool = False) -> dict[str, str]:
    """{'E': text, 'nu': text}: why each measured constant differs from its input, if it does by design
    (``brief``: the nonlinear-curve note in the console's short form)."""
    app = viscoelastic_apparent(data)
    if app is None:
        note = nonlinear_note(data, brief)
        return {"E": note} if note else {}
    why = (f"rate-dependent: the ramp crosses the fit window at t ≈ {app['t_mid']:.3g} s, when the Prony "
           f"terms have relaxed {100 * app['relaxed']:.2g} % of their modulus")
    return {"E": f"{why}; expected ≈ {app['E']:.4g} MPa (quasi-elastic), between the long-term "
                 f"{app['E_inf']:.4g} (input) and the instantaneous {app['E_0']:.4g} MPa",
            "nu": f"{why}; expected ≈ {app['nu']:.4g}, between the long-term {app['nu_inf']:.4g} (input) "
                  f"and the instantaneous {app['nu_0']:.4g}"}
