"""Matplotlib figures from a results dict (never from solver objects): headless Agg backend."""

from __future__ import annotations

from pathlib import Path

from vlab.report import figures as plt  # pyplot-free Agg figures


def _draw_curves(ax, data: dict) -> None:
    """The FE curve of each loaded axis (load cell over extensometer), its analytic homogeneous
    curve dashed where known, and the crosshead-strain curve where there is one."""
    curve, measured = data["curve"], data["measured"]
    for sfx, label in (("", "x"), ("_y", "y")):
        if "strain" + sfx not in curve:
            continue
        strain = [0.0] + curve["strain" + sfx]
        stress = [0.0] + curve["stress" + sfx]
        ax.plot(strain, stress, "o-", ms=3, label=f"FE, load cell / extensometer ({label})")
        ref = (data.get("reference") or {}).get(f"stress_{label}")
        if ref:
            ax.plot(curve["strain" + sfx][: len(ref)], ref, "k--", lw=1,
                    label=f"analytic homogeneous ({label})")
    if "crosshead_strain" in curve and measured.get("E_crosshead") is not None:
        ax.plot([0.0] + curve["crosshead_strain"], [0.0] + curve["stress"], "s:", ms=2, color="tab:gray",
                label=f"FE, load cell / crosshead strain (E would read {measured['E_crosshead']:.4g})")


def plot_stress_strain(data: dict, path: Path) -> None:
    """Engineering stress against extensometer strain, the analytic curve dashed if known,
    the modulus window shaded and the fitted line drawn; beside it the same stress against the
    crosshead (grip-to-grip) strain, which is what a test without an extensometer would plot."""
    curve, measured = data["curve"], data["measured"]
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    _draw_curves(ax, data)
    fit = measured.get("E_fit")
    if fit:
        lo, hi = fit["window"]
        sign = -1.0 if curve["strain"][-1] < 0 else 1.0
        ax.axvspan(sign * lo, sign * hi, color="tab:orange", alpha=0.25,
                   label=f"modulus window {lo:g}–{hi:g}")
    title = f"{data['scene']['name']}: {data['input']['model']}"
    if measured.get("E") is not None:
        title += f"  —  E = {measured['E']:.4g} MPa, ν = {measured['nu']:.4f}"
    ax.set_title(title, fontsize=10)
    if data.get("failure"):  # a stopped or refused test says why, on the figure too
        import textwrap
        ax.text(0.02, 0.97, textwrap.fill("stopped: " + data["failure"]["reason"], 90), fontsize=7,
                color="tab:red", transform=ax.transAxes, va="top")
    ax.set_xlabel("engineering strain [–] (extensometer, unless labelled crosshead)")
    ax.set_ylabel("engineering stress [MPa]")
    ax.axhline(0, color="0.7", lw=0.5)
    ax.axvline(0, color="0.7", lw=0.5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    plt.save(fig, path)
