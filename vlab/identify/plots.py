"""Figures of a fit (matplotlib, no physics): curves with bands and residuals, the stability map."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

from vlab.identify.drucker import PATHS, stability_map  # noqa: E402
from vlab.identify.kinds import FIT_KINDS, outputs_of  # noqa: E402
from vlab.identify.kinds.base import floor_of  # noqa: E402

__all__ = ["plot_curves", "plot_stability_map", "plot_models", "plot_specimens"]

_XLABEL = {"simple-shear": "shear γ", "biaxial": "point", "specimen": "strain", "volumetric": "volume ratio J"}


def _closed_panel(ax, rax, d, cur, confidence: float, label: str, colour: str) -> None:
    """A kind of vlab.identify.kinds: each output block against the control (a second output,
    the axial force of torsion, on a right-hand axis); residuals of every block below."""
    xlabel, ylabels = FIT_KINDS[d.kind].labels
    n, m = len(d.a), len(cur["a"])
    panes = [ax] + [ax.twinx() for _ in outputs_of(d)[1:]]  # a right-hand axis per further output
    for k, (name, axk, style) in enumerate(zip(outputs_of(d), panes, ("o", "s"))):
        yk, ck, bk = d.y[k * n:(k + 1) * n], cur["y"][k * m:(k + 1) * m], cur["band"][k * m:(k + 1) * m]
        axk.plot(d.a, yk, style, color=colour, ms=4, mfc=colour if k == 0 else "none", label=f"{label}: {name}")
        axk.plot(cur["a"], ck, "-" if k == 0 else "--", color="k", lw=1.2)
        axk.fill_between(cur["a"], ck - bk, ck + bk, color="k", alpha=0.18,
                         label=f"{100 * confidence:g} % band (delta method)" if k == 0 else None)
        axk.set_ylabel(ylabels[name])
        floor = floor_of(d)[k * n:(k + 1) * n]
        rel = (cur["at_data"][k * n:(k + 1) * n] - yk) / np.maximum(np.abs(yk), np.where(floor > 0, floor, 1.0))
        rax.plot(d.a, 100 * rel, style + "-", color=colour, ms=3, lw=0.8, mfc=colour if k == 0 else "none",
                 label=name)
    handles = [h for a in panes for h in a.get_legend_handles_labels()[0]]
    ax.legend(handles=handles, fontsize=7, loc="center left" if len(panes) > 1 else "best")
    ax.grid(alpha=0.3)
    rax.axhline(0, color="k", lw=0.6)
    rax.set_ylabel("residual (%)")
    rax.set_xlabel(xlabel)
    rax.grid(alpha=0.3)


def _panel(ax, rax, d, cur, confidence: float):
    held = d.role == "validate"
    colour = "tab:orange" if held else "tab:blue"
    what = d.kind if d.name == d.kind else f"{d.name} ({d.kind})"  # not "uniaxial (uniaxial)"
    label = f"{what}{', held out' if held else ''}"
    if d.kind in FIT_KINDS:
        return _closed_panel(ax, rax, d, cur, confidence, label, colour)
    if d.kind == "biaxial":
        x = np.arange(len(d.y))
        ax.plot(x, d.y, "o", color=colour, ms=4, label=label)
        ax.errorbar(x, cur["y"], yerr=cur["band"], fmt="_", color="k", label="fit ± band")
    else:
        ax.plot(d.a, d.y, "o", color=colour, ms=4, label=label)
        ax.plot(cur["a"], cur["y"], "-", color="k", lw=1.2, label="prediction" if held else "fit")
        ax.fill_between(cur["a"], cur["y"] - cur["band"], cur["y"] + cur["band"], color="k", alpha=0.18,
                        label=f"{100 * confidence:g} % band (delta method)")
        x = d.a
    ax.set_ylabel(_stress_label(d.kind, d.measure))
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    floor = 0.01 * np.max(np.abs(d.y))
    rel = (cur["at_data"] - d.y) / np.maximum(np.abs(d.y), floor if floor > 0 else 1.0)
    rax.axhline(0, color="k", lw=0.6)
    rax.plot(x, 100 * rel, "o-", color=colour, ms=3, lw=0.8)
    rax.set_ylabel("residual (%)")
    rax.set_xlabel(_XLABEL.get(d.kind, "stretch λ"))
    rax.grid(alpha=0.3)


def plot_curves(outcome, curves: dict, path: Path) -> None:
    """One column per data set: data, fitted (or predicted) curve and band; relative residuals below."""
    sets = [d for d in outcome.spec.datasets if d.kind != "specimen"]
    n = len(sets)
    fig, axes = plt.subplots(2, n, figsize=(4.2 * n, 6.0), squeeze=False,
                             gridspec_kw={"height_ratios": [3, 1.3]})
    for j, d in enumerate(sets):
        _panel(axes[0, j], axes[1, j], d, curves[j], outcome.spec.confidence)
    fig.suptitle(f"{outcome.spec.name}: {outcome.data['model']['name']}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _path_segments(ax, outcome, kind: str, lam: np.ndarray, colour: str):
    """A kind's path in the (λ1, λ2) plane: solid where Drucker-stable, dashed where not."""
    from vlab.identify.drucker import _state_eps, min_eigenvalue

    model, x = outcome.spec.model, outcome.x
    l1, l2 = PATHS[kind](lam)
    m = min_eigenvalue(model, x, _state_eps(model, x, kind, lam))
    for mask, style, word in ((m > 0, "-", "stable"), (m <= 0, "--", "unstable")):  # NaN (locked): neither
        y = np.where(mask, l2, np.nan)
        ax.plot(l1, y, style, color=colour, lw=1.6, label=f"{kind} ({word})" if mask.any() else None)


def plot_stability_map(outcome, path: Path) -> None:
    """Where the fitted card is Drucker-stable over (λ1, λ2), 0.1..10 log axes, with the paths."""
    sm = stability_map(outcome.spec.model, outcome.x)
    lam, m = sm["stretch"], sm["min_eigenvalue"]
    fig, ax = plt.subplots(figsize=(6.2, 5.6))
    region = np.where(np.isnan(m), -1.0, (m > 0).astype(float))  # -1: beyond the law's limit (Gent locking)
    # cells, not filled contours: interpolating from -1 to 1 would paint a red seam along the locking edge
    ax.pcolormesh(lam, lam, region.T, shading="nearest", vmin=-1.5, vmax=1.5,
                  cmap=ListedColormap(["#d9d9d9", "#f4c7c3", "#d9ead3"]))
    ax.contour(lam, lam, m.T, levels=[0.0], colors="firebrick", linewidths=0.8)
    path_lam = np.geomspace(0.1, 10.0, 300)
    # no path in green or red: those are the map's stable and unstable regions
    for kind, colour in (("uniaxial", "tab:blue"), ("equibiaxial", "black"), ("planar", "tab:purple")):
        _path_segments(ax, outcome, kind, path_lam, colour)
        for d in (d for d in outcome.spec.datasets if d.kind == kind):  # the data's range, drawn thick
            lam = np.geomspace(float(np.min(d.a)), float(np.max(d.a)), 50)
            l1, l2 = PATHS[kind](lam)
            ax.plot(l1, l2, "-", color=colour, lw=4, alpha=0.5, solid_capstyle="butt")
    ticks = [0.1, 0.2, 0.5, 1, 2, 5, 10]  # plain stretches, not 10⁻¹ … 10¹
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
    ax.set_yticks(ticks, [f"{t:g}" for t in ticks])
    ax.minorticks_off()
    ax.set_xlabel("principal stretch λ1")
    ax.set_ylabel("principal stretch λ2")
    locked = "; grey: chains locked" if np.isnan(m).any() else ""
    ax.set_title(f"Drucker stability (green: stable, red: unstable{locked}; λ3 = 1/(λ1 λ2));\n"
                 "thick: the stretch range of the data", fontsize=9)
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _broken(v: np.ndarray, blocks: int) -> np.ndarray:
    """The blocks of v one after the other with a NaN between them (one line per output)."""
    parts = np.split(np.asarray(v, float), blocks)
    return np.concatenate([np.r_[p, np.nan] for p in parts])[:-1]


def plot_models(spec, ranked, path: Path) -> None:
    """One panel per data set: the data (filled: fitted; open orange: held out) and every ranked
    model's curve, labelled with its rank."""
    from vlab.identify.fitting import curves

    sets = [d for d in spec.datasets if d.kind != "specimen"]
    fig, axes = plt.subplots(1, len(sets), figsize=(4.4 * len(sets), 4.2), squeeze=False)
    for ax, d in zip(axes[0], sets):
        held = d.role == "validate"
        x = np.arange(len(d.y)) if d.kind == "biaxial" else np.tile(d.a, len(d.y) // len(d.a))
        ax.plot(x, d.y, "o", ms=5, mfc="none" if held else "tab:blue", color="tab:orange" if held else "tab:blue",
                label="held out" if held else "fitted data", zorder=5)
        for i, (name, o) in enumerate(ranked, 1):
            cur = curves(o, d)
            style = "_" if d.kind == "biaxial" else "-"
            ax.plot(np.arange(len(cur["y"])) if d.kind == "biaxial" else _broken(np.tile(cur["a"], cur["blocks"]), cur["blocks"]),
                    _broken(np.real(cur["y"]), cur["blocks"]), style, lw=1.2, label=f"{i}. {name}")
        span = float(np.max(d.y) - min(0.0, float(np.min(d.y))))  # a wild prediction must not hide the data
        ax.set_ylim(min(0.0, float(np.min(d.y))) - 0.1 * span, float(np.max(d.y)) + 0.6 * span)
        ax.set_title(f"{d.name} ({d.kind}{', held out' if held else ''})", fontsize=9)
        ax.set_xlabel(FIT_KINDS[d.kind].labels[0] if d.kind in FIT_KINDS else _XLABEL.get(d.kind, "stretch λ"))
        ax.set_ylabel(" and ".join(FIT_KINDS[d.kind].labels[1][o] for o in outputs_of(d)) if d.kind in FIT_KINDS
                      else _stress_label(d.kind, d.measure))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{spec.name}: models against the data", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _stress_label(kind: str, measure: str) -> str:
    """The y label of a homogeneous data set: the pressure of a volumetric test, else the stress
    measure the data give (true or nominal)."""
    if kind == "volumetric":
        return "pressure (MPa)"
    return f"{'true' if measure == 'true' else 'nominal'} stress (MPa)"


def plot_specimens(name: str, panels: list[dict], path: Path) -> None:
    """One panel per kind (vlab.identify.specimens.band_panels, record_band_panels: a panel may
    bring its own xlabel, ylabel and log_x): the envelope of the specimens' fitted curves (grey
    band), each specimen's curve and data in its colour, the pooled fit (black)."""
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 4.2), squeeze=False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, p in zip(axes[0], panels):
        ax.fill_between(p["a"], p["lo"], p["hi"], color="0.6", alpha=0.35, label="specimens' fits (envelope)")
        ids = list(p["curves"])
        for s, a, y in p["data"]:
            c = colours[ids.index(s) % len(colours)] if s in ids else "0.4"
            ax.plot(a, y, "o", ms=3, color=c, label=f"specimen {s}")
        for j, (s, y) in enumerate(p["curves"].items()):
            ax.plot(p["a"], y, "-", lw=0.8, color=colours[j % len(colours)])
        ax.plot(p["a"], p["pooled"], "-", color="k", lw=1.6, label="pooled fit (the card)")
        ax.set_xlabel(p.get("xlabel") or _XLABEL.get(p["kind"], "stretch λ"))
        ax.set_ylabel(p.get("ylabel") or _stress_label(p["kind"], p["measure"]))
        if p.get("log_x"):
            ax.set_xscale("log")
        ax.set_title(p["kind"], fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{name}: specimens and the pooled fit", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
