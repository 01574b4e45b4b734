"""The biaxial test's own figures (results dicts only; no physics beyond drawing the input's
small-strain line):

- stress against strain along x and along y, side by side: load-cell force / A0 against the
  extensometer strain of that axis (FE, solid), the analytic homogeneous curve (dashed) where the
  specimen has one, and for a cruciform the FE centre stress against the centre strain (dotted);
- the thickness strain against the in-plane strain sum ε_x + ε_y, with the small-strain line of
  the input, ε_z = −ν/(1 − ν) (ε_x + ε_y) (isotropic, σ_z = 0), and the constants the kind
  measures (E, ν from both axes) in the titles.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab.report import figures as plt  # pyplot-free Agg figures
from vlab.report.comparison_plots import colour

AXES = (("x", ""), ("y", "_y"))


def constants_text(data: dict) -> str:
    """E and ν as this biaxial test measured them (per axis when fitted per axis)."""
    m = data["measured"]
    if m.get("E") is None:
        return "E, ν not measured"
    axes = [a for a in (m.get("axes") or []) if a.get("axis") in ("x", "y")]
    per = "; ".join(f"{a['axis']}: E {a['E']:.4g}" for a in axes) if axes[1:] else ""  # both axes fitted
    return f"E = {m['E']:.4g} MPa, ν = {m['nu']:.4f}" + (f" ({per})" if per else "")


def _analytic(data: dict, sfx: str, true: bool):
    ref = data.get("reference") or {}
    P = ref.get("stress" + ("_y" if sfx else "_x"))
    if not P or true:
        return None
    lam = np.asarray(data["curve"]["stretch" + sfx][:len(P)], dtype=float)
    return np.r_[0.0, lam - 1.0], np.r_[0.0, P]


def plot_biaxial_stress_strain(datas: list[dict], path: Path, true: bool = False) -> None:
    """Stress–strain along x (left) and y (right) for every model."""
    kind = "true" if true else "engineering"
    fig, axes = plt.subplots(1, 2, figsize=(10.4, 4.4), dpi=120, sharey=True)
    for ax, (name, sfx) in zip(axes, AXES):
        for d in datas:
            c, curve = colour(d["input"]["model"]), d["curve"]
            x = curve[("true_strain" if true else "strain") + sfx]
            y = curve[("true_stress" if true else "stress") + sfx]
            ax.plot(np.r_[0.0, x], np.r_[0.0, y], "-o", ms=2.5, lw=1.5, color=c, label=f"{d['input']['model']} (FE)")
            ref = _analytic(d, sfx, true)
            if ref is not None:
                ax.plot(*ref, "--", color="0.15", lw=0.9, zorder=4, label="analytic homogeneous")
            centre = curve.get(f"centre_stress_{name}")
            if centre and not true:
                ax.plot(np.r_[0.0, curve[f"centre_strain_{name}"]], np.r_[0.0, centre], ":", lw=1.6, color=c,
                        label="centre stress vs centre strain (FE average)")
        ax.set_xlabel(f"{'true ' if true else ''}extensometer strain ε_{name} [–]")
        ax.set_title(f"along {name}", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper left")
    axes[0].set_ylabel(f"{kind} stress [MPa]")
    title = constants_text(datas[0]) if len(datas) == 1 else f"{len(datas)} models"
    fig.suptitle(f"Biaxial {kind} stress–strain, {datas[0]['input']['model'] if len(datas) == 1 else ''} {title}",
                 fontsize=11)
    plt.save(fig, path)


def plot_thickness(datas: list[dict], path: Path) -> None:
    """Thickness strain against ε_x + ε_y, with the input's small-strain line."""
    fig, ax = plt.subplots(figsize=(7.2, 4.4), dpi=120)
    span = 0.0
    for d in datas:
        curve = d["curve"]
        s = np.r_[0.0, np.asarray(curve["strain"]) + np.asarray(curve["strain_y"])]
        ax.plot(s, np.r_[0.0, curve["thickness_strain"]], "-o", ms=2.5, color=colour(d["input"]["model"]),
                label=f"{d['input']['model']}: {constants_text(d)}")
        span = max(span, float(np.max(np.abs(s))))
    nu = datas[0]["input"]["nu"]
    line = np.linspace(-span, span, 2) if any(np.min(np.r_[0.0, d["curve"]["strain"]]) < 0 for d in datas) \
        else np.linspace(0.0, span, 2)
    ax.plot(line, -nu / (1.0 - nu) * line, "k:", lw=1, label=f"small strain, σ_z = 0: −ν/(1−ν)(ε_x+ε_y), input ν = {nu:g}")
    ax.set_xlabel("in-plane strain sum ε_x + ε_y [–]")
    ax.set_ylabel("thickness strain ε_z [–]")
    ax.set_title("Thickness against in-plane strain", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    plt.save(fig, path)
