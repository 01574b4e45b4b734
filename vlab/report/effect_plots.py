"""Figures of the time-dependent protocols, from results dicts: hysteresis loops (load–unload,
cyclic), relaxation (stress against time under a held strain) and creep (strain against time
under a held force). A monotonic untimed test gets none of them. Columns follow the test kind
(vlab.report.kind_rows.kind_of_data): a simple-shear test plots its shear force against the
amount of shear γ (plate travel / gap) and relaxes its shear stress."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab.report import figures as plt  # pyplot-free Agg figures

MODEL_STYLES = ("-", "--", ":", "-.")  # several models on one loop figure: the cycles keep the colours


def _axes(data: dict) -> tuple[str, str, str, str]:
    """(x column, force column, stress column, x label) of the loops and relaxation plots."""
    from vlab.report.kind_rows import kind_of_data

    if kind_of_data(data).load_key == "shear":
        return "shear", "shear_force", "shear_stress", "amount of shear γ (plate travel / gap) [–]"
    return ("crosshead_strain", "force", "stress",
            "grip extension / grip separation (crosshead strain) [–]")


def _relaxation_words(data: dict) -> tuple[str, str]:
    """(y label, what is held) of the relaxation figure."""
    from vlab.report.kind_rows import kind_of_data

    if kind_of_data(data).load_key == "shear":
        return "nominal shear stress F_s / A₀ [MPa]", "relaxation under a held amount of shear"
    return "engineering stress [MPa]", "relaxation under a held grip stretch"


def _protocol(data: dict) -> dict:
    return ((data.get("effects") or {}).get("protocol")) or {"name": "monotonic"}


def effect_figures(datas: list[dict], folder: Path) -> list:
    """Draw the figures the runs' protocols call for; returns html Figures."""
    from vlab.report.html import Figure

    figures = []
    names = {_protocol(d)["name"] for d in datas}
    if names & {"load-unload", "cyclic"}:
        _hysteresis(datas, folder / "hysteresis.png")
        figures.append(Figure("hysteresis.png", "Load against crosshead travel over the whole protocol, one "
                              "colour per cycle (a cycle: from where the crosshead turns back to load "
                              "until it turns back again); the area enclosed by a loop is the energy "
                              "dissipated in that cycle, and a reload below the first loading is "
                              "softening (Mullins)."))
    if "relaxation" in names:
        ylabel, what = _relaxation_words(datas[0])
        _against_time(datas, folder / "relaxation.png", _axes(datas[0])[2], ylabel, what)
        figures.append(Figure("relaxation.png", "Stress against time: the ramp, then the held "
                              f"{'shear' if 'shear' in what else 'stretch'}."))
    if "creep" in names:
        _against_time(datas, folder / "creep.png", "strain", "extensometer strain [–]",
                      "creep under a held force")
        figures.append(Figure("creep.png", "Extensometer strain against time: the ramp, then the held force."))
    return figures


def _label(data: dict) -> str:
    declared = (data.get("effects") or {}).get("declared") or {}
    return " + ".join([data["input"]["model"], *declared])


def _finish(fig, ax, path: Path, title: str) -> list[dict]:
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    return plt.save(fig, path)


def cycle_starts(control) -> list[int]:
    """Indices where a cycle starts in a control column (grip strain, γ) with its origin first: 0,
    then every reading where the control turns from falling to rising (a local minimum; held
    readings in between are skipped). Load–unload: one cycle; cyclic: one per amplitude. A last
    stretch that only rises (fully reversed shear's −γₙ → 0, back to rest) ends the last cycle."""
    x = np.asarray(control, dtype=float)
    starts, falling = [0], False
    for i in range(1, len(x)):
        step = x[i] - x[i - 1]
        if step > 0 and falling:
            starts.append(i - 1)
        if step != 0:
            falling = step < 0
    if len(starts) > 1 and np.all(np.diff(x[starts[-1]:]) >= 0):
        starts.pop()
    return starts


def _hysteresis(datas: list[dict], path: Path) -> list[dict]:
    """Force against the crosshead (mm where results.json gives the grip separation, else strain;
    simple shear: γ), a colour per cycle numbered in the legend with its peak, a line style per model."""
    import matplotlib as mpl

    from vlab.report.comparison_plots import crosshead_displacement

    fig, ax = plt.subplots(figsize=(7.6, 4.8), dpi=120)
    x_col, f_col, _, xlabel = _axes(datas[0])
    in_mm = x_col == "crosshead_strain" and all(crosshead_displacement(d) is not None for d in datas)
    n_cycles = max(len(cycle_starts([0.0] + d["curve"][x_col])) for d in datas)
    cmap = mpl.colormaps["viridis"]
    for m, d in enumerate(datas):
        c = d["curve"]
        x = crosshead_displacement(d) if in_mm else np.r_[0.0, c[x_col]]
        f = np.r_[0.0, c[f_col]]
        starts = cycle_starts([0.0] + c[x_col]) + [len(x) - 1]
        for k, (a, b) in enumerate(zip(starts[:-1], starts[1:])):
            colour = cmap(0.85 * k / max(n_cycles - 1, 1))
            peak = x[a:b + 1][np.argmax(np.abs(x[a:b + 1]))]
            name = f"cycle {k + 1}: to {peak:.3g}{' mm' if in_mm else ''}"
            ax.plot(x[a:b + 1], f[a:b + 1], MODEL_STYLES[m % len(MODEL_STYLES)], marker="o", ms=2, color=colour,
                    label=name if len(datas) == 1 else f"{_label(d)}, {name}")
        if len(x) > 2:
            ax.annotate("", xy=(x[2], f[2]), xytext=(x[1], f[1]), arrowprops={"arrowstyle": "->", "color": "0.4"})
    ax.set_xlabel("crosshead (grip) displacement Δ = (λ − 1) L₀ [mm]" if in_mm else xlabel)
    ax.set_ylabel("load-cell force [N]")
    ax.axhline(0, color="0.7", lw=0.5)
    title = f"{datas[0]['scene']['name']}: {_protocol(datas[0])['name']}, {n_cycles} cycle{'s' * (n_cycles > 1)}"
    if len(datas) == 1:
        title += f" ({_label(datas[0])})"
    return _finish(fig, ax, path, title)


def _against_time(datas: list[dict], path: Path, column: str, ylabel: str, what: str) -> None:
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    ramp_ends = []
    for d in datas:
        c = d["curve"]
        if "time" not in c:
            continue
        ax.plot([0.0] + c["time"], [0.0] + c[column], "o-", ms=2, label=_label(d))
        ramp_ends.append(c["time"][max(0, len(c["time"]) - (_protocol(d).get("hold_steps") or 0) - 1)])
        ax.axvline(ramp_ends[-1], color="0.6", ls=":", lw=1)
    if ramp_ends:
        ax.set_xscale("symlog", linthresh=min(ramp_ends))
        ax.set_xlim(left=0.0)
    ax.set_xlabel("time [s] (linear up to the end of the ramp, logarithmic beyond; dotted: hold starts)")
    ax.set_ylabel(ylabel)
    _finish(fig, ax, path, f"{datas[0]['scene']['name']}: {what}")
