"""Figures that put several models' results dicts on the same axes (Agg backend, no physics here:
every number comes from the results dicts; the analytic curve is each dict's ``reference``).

Stress–strain overlay, engineering (load-cell force / A0 against extensometer strain) or true
(force / current area against ln(1 + strain)); the analytic homogeneous response is converted the
same way from its nominal stress P and lateral stretch t:
    uniaxial  λ = grip stretch, σ_true = P / t²,       biaxial  σ_true,x = P_x / (λ_y t).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.ticker
import numpy as np

from vlab.report import figures as plt  # pyplot-free Agg figures

COLOURS = {"linear": "tab:blue", "stvk": "tab:orange", "stvk-volumetric": "tab:brown",
           "neo-hookean": "tab:green", "spring-network": "tab:purple", "mooney-rivlin": "tab:red",
           "yeoh": "tab:pink", "ogden": "tab:olive", "gent": "tab:cyan", "arruda-boyce": "navy"}
_SPARE = ("darkgoldenrod", "teal", "indigo", "crimson", "slategray", "darkorange", "forestgreen", "orchid")
DEPARTURE_MARKERS = {"5%": ("o", "none"), "10%": ("X", None)}


def colour(model: str) -> str:
    """A model's (or a [compare] label's) colour; labels get a fixed spare colour by their name."""
    import zlib

    return COLOURS.get(model) or _SPARE[zlib.crc32(model.encode()) % len(_SPARE)]


def label(d: dict) -> str:
    """The name a run is shown under: its [compare] label, else its model."""
    return d["input"].get("label", d["input"]["model"])


def measured_curve(data: dict, true: bool) -> tuple[np.ndarray, np.ndarray]:
    """(strain, stress) of axis x with the unloaded origin prepended."""
    c = data["curve"]
    x, y = (c["true_strain"], c["true_stress"]) if true else (c["strain"], c["stress"])
    return np.r_[0.0, x], np.r_[0.0, y]


def analytic_curve(data: dict, true: bool) -> tuple[np.ndarray, np.ndarray] | None:
    """The homogeneous solution at the recorded grip stretches, or None if the scene has none."""
    ref = data.get("reference") or {}
    P = ref.get("stress_x")
    if not P:
        return None
    n = len(P)
    lam = np.asarray(data["curve"]["stretch"][:n])
    P = np.asarray(P)
    if not true:
        return np.r_[0.0, lam - 1.0], np.r_[0.0, P]
    t = np.asarray(ref["lateral_stretch"][:n])
    lam_y = np.asarray(data["curve"]["stretch_y"][:n]) if "stretch_y" in data["curve"] else t
    return np.r_[0.0, np.log(lam)], np.r_[0.0, P / (lam_y * t)]


def _window(datas: list[dict]) -> tuple[float, float, float] | None:
    """The |strain| window of the E fit and the sign of the test's strain (−1 in compression)."""
    for d in datas:
        window = d["measured"].get("window") or (d["measured"].get("E_fit") or {}).get("window")
        if window and None not in window and d["measured"].get("E") is not None:
            strain = np.asarray(d["curve"]["strain"], dtype=float)
            # the side of the largest reading: a cyclic test ends near zero strain
            sign = -1.0 if strain.size and strain[np.argmax(np.abs(strain))] < 0 else 1.0
            return window[0], window[1], sign
    return None


def _draw_curves(ax, datas, true, departures, marker_size=4):
    for d in datas:
        model, c = label(d), colour(label(d))
        x, y = measured_curve(d, true)
        ax.plot(x, y, "-", marker="o", ms=marker_size * 0.7, color=c, lw=1.6, label=f"{model} (FE)")
        centre = d["curve"].get("centre_stress_x")
        if centre and not true:  # cruciform: the FE centre stress vs centre strain, beside the nominal
            ax.plot(np.r_[0.0, d["curve"]["centre_strain_x"]], np.r_[0.0, centre], ":", color=c, lw=1.6,
                    label=f"{model} centre stress (FE average)")
        ref = analytic_curve(d, true)
        if ref is not None:  # on top, thin and dark, so it shows where it coincides with FE
            ax.plot(*ref, "--", color="0.15", lw=0.9, zorder=4)
        for key, strain in (departures.get(model) or {}).items():
            if strain is not None:
                marker, face = DEPARTURE_MARKERS[key]
                ax.plot(*_point_on_curve(d, strain, true), marker=marker, ms=9, color=c,
                        mfc=face or c, mew=1.5, ls="none", zorder=5)


def _point_on_curve(data: dict, strain: float, true: bool) -> tuple[list[float], list[float]]:
    """The curve's point at an engineering extensometer strain, in the plotted measures."""
    xm, ym = measured_curve(data, False)
    xt, yt = measured_curve(data, True)
    order = np.argsort(xm)
    x, y = (xt, yt) if true else (xm, ym)
    return [float(np.interp(strain, xm[order], x[order]))], [float(np.interp(strain, xm[order], y[order]))]


def crosshead_displacement(data: dict) -> np.ndarray | None:
    """The crosshead (grip) displacement Δ = (λ − 1) L₀ in mm at each reading, the unloaded origin
    first; L₀ the initial grip separation (results.json → specimen). None where either is missing."""
    L0 = ((data.get("specimen") or {}).get("grip_separation") or {}).get("x")
    strain = data["curve"].get("crosshead_strain")
    if L0 is None or strain is None:
        return None
    return np.r_[0.0, strain] * L0


def _draw_machine(ax, datas: list[dict]) -> None:
    """The machine's own record: load-cell force F (N) against crosshead displacement Δ (mm), every
    reading of the whole protocol (loops included), before any specimen dimension enters but L₀."""
    for d in datas:
        delta = crosshead_displacement(d)
        if delta is not None:
            ax.plot(delta, np.r_[0.0, d["curve"]["force"]], "-", marker="o", ms=2.5, lw=1.4,
                    color=colour(label(d)), label=f"{label(d)} (FE)")
    ax.set_xlabel("crosshead (grip) displacement Δ = (λ − 1) L₀ [mm]")
    ax.set_ylabel("load-cell force F [N]")
    ax.set_title("Machine record: force against crosshead displacement", fontsize=11)
    ax.axhline(0, color="0.7", lw=0.5)
    ax.axvline(0, color="0.7", lw=0.5)
    ax.grid(alpha=0.3)


def plot_overlay(datas: list[dict], path: Path, true: bool = False,
                 departures: dict[str, dict] | None = None) -> list[dict]:
    """Stress–strain curves of all models, analytic dashed, fit window shaded with an inset zoom,
    departure from Neo-Hookean marked (○ 5 %, ✕ 10 %); beside them, where the results give the
    grip separation, the machine's force–crosshead record. Returns the panels (figures.describe)."""
    departures = departures or {}
    machine = any(crosshead_displacement(d) is not None for d in datas)
    if machine:
        fig, (ax, right) = plt.subplots(1, 2, figsize=(15.0, 5.4), dpi=120, gridspec_kw={"width_ratios": [1.2, 1.0]})
        _draw_machine(right, datas)
    else:
        fig, ax = plt.subplots(figsize=(9.6, 5.4), dpi=120)
        right = ax
    _draw_curves(ax, datas, true, departures)
    window = _window(datas)
    if window is not None:
        lo, hi, sign = window
        xs = sorted((sign * lo, sign * hi))
        if true:
            xs = [float(np.log1p(v)) for v in xs]
        ax.axvspan(*xs, color="gold", alpha=0.35, lw=0)
        _inset(ax, datas, true, xs, sign)
    kind = "true" if true else "engineering"
    ax.set_xlabel(f"{'true strain ln(1 + ε)' if true else 'extensometer strain ε (engineering)'} [–]")
    ax.set_ylabel(f"{kind} stress [MPa]")
    if len(datas) == 1:
        m = datas[0]["measured"]
        fitted = f": E = {m['E']:.4g} MPa, ν = {m['nu']:.4f}" if m.get("E") is not None else ""
        title = f"{kind.capitalize()} stress–strain, {datas[0]['input']['model']}{fitted}"
    else:
        title = f"{kind.capitalize()} stress–strain, {len(datas)} models"
    ax.set_title(title, fontsize=11)
    ax.axhline(0, color="0.7", lw=0.5)
    ax.axvline(0, color="0.7", lw=0.5)
    ax.grid(alpha=0.3)
    right.legend(handles=_legend_handles(datas, departures, window), fontsize=8, loc="upper left",
                 bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    return plt.save(fig, path)


def _legend_handles(datas, departures, window):
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = [Line2D([], [], color=colour(label(d)), marker="o", ms=3,
                      label=f"{label(d)} (FE)") for d in datas]
    if any(analytic_curve(d, False) is not None for d in datas):
        handles.append(Line2D([], [], color="0.3", ls="--", label="analytic homogeneous (each model)"))
    if any(d["curve"].get("centre_stress_x") for d in datas):
        handles.append(Line2D([], [], color="0.3", ls=":", label="centre stress vs centre strain (FE average)"))
    if window is not None:
        handles.append(Patch(color="gold", alpha=0.35, label=f"E fit window |ε| {window[0]:g}–{window[1]:g}"))
    if any(v for dep in departures.values() for v in dep.values()):
        handles.append(Line2D([], [], color="0.3", marker="o", mfc="none", ls="none", label="departs from Neo-Hookean by 5 %"))
        handles.append(Line2D([], [], color="0.3", marker="X", ls="none", label="departs from Neo-Hookean by 10 %"))
    return handles


def _first_loading(x: np.ndarray) -> int:
    """Length of the first loading ramp: readings up to the first fall of |strain|."""
    falls = np.flatnonzero(np.diff(np.abs(x)) < 0)
    return int(falls[0]) + 1 if falls.size else len(x)


def _inset(ax, datas, true, xs, sign):
    """Zoom on the fit window (it spans a few tenths of a percent of strain)."""
    inset = ax.inset_axes([0.07, 0.55, 0.36, 0.36] if sign > 0 else [0.57, 0.08, 0.36, 0.36])
    x_lo, x_hi = (0.0, 1.6 * xs[1]) if sign > 0 else (1.6 * xs[0], 0.0)
    y_hi = 0.0
    for d in datas:
        x, y = measured_curve(d, true)
        x, y = x[:_first_loading(x)], y[:_first_loading(x)]  # where E is fitted (unloading excluded)
        inside = (x >= min(x_lo, x_hi)) & (x <= max(x_lo, x_hi))
        inset.plot(x[inside], y[inside], "-o", ms=2.5, lw=1.0, color=colour(label(d)))
        if inside.any():
            y_hi = max(y_hi, float(np.max(np.abs(y[inside]))))
        fit = d["measured"].get("E_fit")
        if fit and not true and "strain_y" not in d["curve"]:  # the fit is s against ε (uniaxial)
            line = np.linspace(x_lo, x_hi, 2)
            inset.plot(line, fit["intercept"] + fit["slope"] * line, ":", lw=0.8, color=colour(label(d)))
    inset.axvspan(*xs, color="gold", alpha=0.35, lw=0)
    inset.set_xlim(min(x_lo, x_hi), max(x_lo, x_hi))
    if y_hi > 0:
        inset.set_ylim(*(sorted((0.0, sign * 1.1 * y_hi))))
    inset.set_title("fit window" + ("" if true else " (dotted: fitted lines, uniaxial)"), fontsize=7)
    inset.tick_params(labelsize=6)
    inset.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(4))
    inset.grid(alpha=0.3)


def lateral_strain(data: dict) -> tuple[np.ndarray, str]:
    """The strain across the load: width (uniaxial) or thickness (biaxial)."""
    c = data["curve"]
    if "strain_y" in c:
        return np.r_[0.0, c["thickness_strain"]], "thickness strain"
    return np.r_[0.0, c["transverse_strain"]], "transverse (width) strain"


def plot_lateral(datas: list[dict], path: Path) -> None:
    """Left: lateral against axial strain. Right: apparent Poisson's ratio −ε_lat/ε_axial as strain grows."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.0, 4.2), dpi=120)
    which = "lateral strain"
    for d in datas:
        model, c = label(d), colour(label(d))
        axial = np.r_[0.0, d["curve"]["strain"]]
        lateral, which = lateral_strain(d)
        left.plot(axial, lateral, "-o", ms=2.5, color=c, label=model)
        nonzero = np.abs(axial) > 0
        right.plot(axial[nonzero], -lateral[nonzero] / axial[nonzero], "-o", ms=2.5, color=c, label=model)
    nu = datas[0]["input"]["nu"]  # the first model's (a [compare] card may imply another)
    span = np.array([0.0, max(np.r_[0.0, d["curve"]["strain"]].max() for d in datas)])
    left.plot(span, -nu * span, "k:", lw=1, label=f"small-strain slope −ν, ν = {nu:g}")
    right.axhline(nu, color="k", ls=":", lw=1, label=f"input ν = {nu:g}")
    left.set_xlabel("axial extensometer strain [–]")
    left.set_ylabel(f"{which} [–]")
    left.set_title("Lateral against axial strain", fontsize=10)
    right.set_xlabel("axial extensometer strain [–]")
    right.set_ylabel("apparent Poisson's ratio −ε_lat / ε_axial [–]")
    right.set_title("Apparent Poisson's ratio as strain grows", fontsize=10)
    for ax in (left, right):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    plt.save(fig, path)
