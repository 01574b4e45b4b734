"""Figures and table rows of the test kinds that are not uniaxial or biaxial (planar, simple
shear), from results dicts only: each kind's own axes (vlab.loading.kinds: ``plot``), no
"uniaxial" labels and no apparent Poisson's ratio where the width is held or sheared.

- planar: nominal stress F/A₀ against the grip stretch λ (analytic pure shear dashed where the
  set-up has it); beside it the thickness and transverse strains against λ (the width is held, so
  the transverse strain stays ≈ 0 on the block and small at the strip's centre).
- simple shear: nominal shear stress τ = F_s/A₀ and normal stress σ_n = F_n/A₀ on the moving plate
  against the gauge-mark shear γ (analytic dashed against the plate γ); beside it the FE
  centre-average normal-stress difference N₁ = σ₁₁ − σ₂₂ against γ.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab.report import figures as plt  # pyplot-free Agg figures
from vlab.report.comparison_plots import colour
from vlab.report.kind_rows import kind_of_data

__all__ = ["kind_of_data", "plot_kind", "KIND_CAPTIONS"]

KIND_CAPTIONS = {
    "planar": ("Planar tension (pure shear): nominal stress F/A₀ against grip stretch for every model; dashed: "
               "the analytic pure-shear state F = diag(λ, 1, t) where the set-up has one. Right: thickness and "
               "transverse strain at the gauge centre (the width is held by the grips: no apparent Poisson's ratio)."),
    "simple-shear": ("Simple shear: nominal shear stress τ = F_s/A₀ (solid) and normal stress σ_n = F_n/A₀ "
                     "(dotted) on the moving plate against the gauge-mark shear γ; dashed: the analytic simple "
                     "shear F = I + γ e₁⊗e₂ where the set-up has one. Right: the normal-stress difference "
                     "N₁ = σ₁₁ − σ₂₂ of the FE centre average (Poynting effect)."),
    "confined-compression": ("Confined compression in a frictionless rigid die: axial nominal stress F/A₀ against "
                             "the platen stretch λ; dashed: the homogeneous state F = diag(λ, 1, 1). Right: the "
                             "pressure p = −tr σ/3 (FE volume average) against the volume ratio J = V/V₀, "
                             "whose initial slope is the bulk modulus K."),
    "torsion": ("Torsion of a cylinder: torque T about the axis against the twist per unit length ψ. Right: the "
                "axial force N on the turning grip with the length held (negative: the Poynting effect pulls "
                "the ends together), or the axial stretch with the end free (it lengthens)."),
    "inflation": ("Inflation of a spherical shell under volume control: cavity pressure against the inner hoop "
                  "stretch λ_a; dashed: the incompressible thick-sphere closed form; the marker: the pressure "
                  "maximum (measured.limit_point), which pressure control could not pass. Right: the outer "
                  "hoop stretch λ_b against λ_a (incompressible: λ_b³ = 1 + (λ_a³ − 1) A³/B³). A clamped "
                  "membrane (the bulge test): the liquid's pressure against the pole stretch; right: the pole "
                  "stress, the lab's p R_c / (2t) and the FE's, against the pole stretch; dashed: the "
                  "equibiaxial membrane stress of the card at that stretch."),
}


def _with_origin(values) -> np.ndarray:
    return np.r_[0.0, np.asarray(values, dtype=float)]


def _main_panel(ax, datas: list[dict], kind) -> None:
    spec = kind.plot
    origin = 1.0 if spec.x == "stretch" else 0.0
    for d in datas:
        c, curve, ref = colour(d["input"]["model"]), d["curve"], d.get("reference") or {}
        for i, (x, y, key) in enumerate(spec.series):
            style = "-" if i == 0 else ":"
            ax.plot(np.r_[origin, curve[x]], _with_origin(curve[y]), style, marker="o", ms=2.5, color=c,
                    label=f"{d['input']['model']} {y.replace('_', ' ')} (FE)")
            if ref.get(key):
                n = len(ref[key])
                ax.plot(np.r_[origin, curve[spec.reference_x][:n]], _with_origin(ref[key]), "--", color="0.15",
                        lw=0.9, zorder=4)
    ax.set_xlabel(spec.xlabel)
    ax.set_ylabel(spec.ylabel)
    ax.axhline(0, color="0.7", lw=0.5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def _side_panel(ax, datas: list[dict], kind) -> None:
    """The kind's side quantity (module docstring) for every model, labelled."""
    draw = _SIDE_CURVES.get(kind.name, _shear_side)
    for d in datas:
        draw(ax, d, colour(d["input"]["model"]), d["curve"])
    xlabel, ylabel, title = _side_labels(datas, kind)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    elif kind.name == "simple-shear":  # a history material ([effects]) records no FE centre stress
        ax.text(0.5, 0.5, "no FE centre stress recorded\n(history-dependent material: [effects])",
                ha="center", va="center", transform=ax.transAxes, fontsize=8, color="0.4")


def _free_end(d: dict) -> bool:
    """Whether a torsion test leaves the axial end free (else the length is held)."""
    return d["scene"]["source"]["test"].get("axial") == "free"


def _planar_side(ax, d: dict, c, curve: dict) -> None:
    """Thickness and (held) transverse strain at the gauge centre against the grip stretch."""
    ax.plot(np.r_[1.0, curve["stretch"]],
            _with_origin(curve["thickness_strain"]), "-o", ms=2.5, color=c, label=f"{d['input']['model']} thickness")
    ax.plot(np.r_[1.0, curve["stretch"]], _with_origin(curve["transverse_strain"]), ":", color=c,
            label=f"{d['input']['model']} transverse (held)")


def _torsion_side(ax, d: dict, c, curve: dict) -> None:
    """The axial stretch (free end, from 1) or the axial force N (length held, from 0) against ψ."""
    free = _free_end(d)
    ax.plot(_with_origin(curve["twist"]), np.r_[1.0 if free else 0.0,
                                               curve["axial_stretch" if free else "axial_force"]],
            "-o", ms=2.5, color=c, label=f"{d['input']['model']} {'axial stretch' if free else 'N'} (FE)")


def _bulge(d: dict) -> bool:
    """An inflation record of the bulge test (a membrane), not of a balloon."""
    return "pole_height" in d["curve"]


def _inflation_side(ax, d: dict, c, curve: dict) -> None:
    """λ_b against λ_a (a balloon) or the pole stresses against the pole stretch (a bulge); the
    pressure maximum (measured.limit_point) marked on the main panel."""
    if _bulge(d):
        ax.plot(np.r_[1.0, curve["stretch"]], _with_origin(curve["pole_stress"]), "-o", ms=2.5, color=c,
                label=f"{d['input']['model']} lab p R_c / (2t)")
        if curve.get("pole_stress_fe"):
            ax.plot(np.r_[1.0, curve["stretch"]], _with_origin(curve["pole_stress_fe"]), ":s", ms=2.5, color=c,
                    label=f"{d['input']['model']} FE")
        ref = (d.get("reference") or {}).get("pole_stress")
        if ref:
            ax.plot(np.r_[1.0, curve["stretch"]], _with_origin(ref), "--", color="0.15", lw=0.9,
                    label="equibiaxial σ(λ) of the card")
        ax.figure.axes[0].set_xlabel("pole stretch λ [–]")
    else:
        ax.plot(np.r_[1.0, curve["stretch"]], np.r_[1.0, curve["outer_stretch"]], "-o", ms=2.5, color=c,
                label=f"{d['input']['model']} λ_b (FE)")
    limit = (d.get("measured") or {}).get("limit_point")
    if limit:
        left = ax.figure.axes[0]
        left.plot([limit["stretch"]], [limit["pressure"]], "v", ms=8, color=c, zorder=5,
                  label=f"limit point {'λ' if _bulge(d) else 'λ_a'} = {limit['stretch']:.4g}")
        left.legend(fontsize=7)


def _confined_side(ax, d: dict, c, curve: dict) -> None:
    """The pressure p against J (FE, and the homogeneous reference dashed where there is one)."""
    if curve.get("pressure"):
        ax.plot(np.r_[1.0, curve["volume_ratio"]], _with_origin(curve["pressure"]), "-o", ms=2.5,
                color=c, label=f"{d['input']['model']} p (FE)")
    ref = d.get("reference") or {}
    if ref.get("pressure"):
        ax.plot(np.r_[1.0, ref["volume_ratio"]], _with_origin(ref["pressure"]), "--", color="0.15", lw=0.9)


def _shear_side(ax, d: dict, c, curve: dict) -> None:
    """N₁ = σ₁₁ − σ₂₂ of the FE centre average against the gauge-mark γ (where it was recorded)."""
    if "centre_cauchy_xx" in curve:
        N1 = np.asarray(curve["centre_cauchy_xx"]) - np.asarray(curve["centre_cauchy_yy"])
        ax.plot(_with_origin(curve["shear_gauge"]), _with_origin(N1), "-o", ms=2.5, color=c,
                label=f"{d['input']['model']} N₁ (FE centre)")


_SIDE_CURVES = {"planar": _planar_side, "torsion": _torsion_side, "inflation": _inflation_side,
                "confined-compression": _confined_side}
_SIDE_LABELS = {
    "planar": ("grip stretch λ [–]", "strain at the gauge centre [–]", "Thickness and transverse strain"),
    "inflation": ("inner hoop stretch λ_a [–]", "outer hoop stretch λ_b [–]",
                  "Wall thinning: outer against inner stretch"),
    "confined-compression": ("volume ratio J = V/V₀ [–]", "pressure p = −tr σ/3 [MPa]",
                             "Pressure against volume (bulk modulus)"),
    "simple-shear": ("shear strain γ [–] (gauge marks)", "N₁ = σ₁₁ − σ₂₂ [MPa]", "Normal-stress difference (Poynting)"),
}


def _side_labels(datas: list[dict], kind) -> tuple[str, str, str]:
    """(x label, y label, title) of the side panel (torsion's depend on its axial end)."""
    if kind.name == "torsion":
        free = _free_end(datas[0])
        return ("twist ψ [rad/mm]", "axial stretch [–]" if free else "axial force N [N]",
                "Poynting effect: " + ("the free end lengthens" if free else "axial force, length held"))
    if kind.name == "inflation" and _bulge(datas[0]):
        return ("pole stretch λ [–]", "pole stress [MPa]", "Bulge test: the pole stress, lab estimate and FE")
    return _SIDE_LABELS.get(kind.name, _SIDE_LABELS["simple-shear"])


def plot_kind(datas: list[dict], path: Path) -> None:
    """The kind's main figure (module docstring): its curves left, its side quantity right."""
    kind = kind_of_data(datas[0])
    fig, (left, right) = plt.subplots(1, 2, figsize=(11.0, 4.6), dpi=120)
    _main_panel(left, datas, kind)
    _side_panel(right, datas, kind)
    title = {"planar": "Planar tension (pure shear)", "simple-shear": "Simple shear",
             "confined-compression": "Confined compression", "torsion": "Torsion",
             "inflation": "Inflation"}.get(kind.name, kind.name)
    left.set_title(f"{title}: {', '.join(d['input']['model'] for d in datas)}", fontsize=10)
    plt.save(fig, path)
