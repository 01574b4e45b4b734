"""Figures of the time-dependent protocols, from results dicts: hysteresis loops (load–unload,
cyclic), relaxation (stress against time under a held strain) and creep (strain against time
under a held force). A monotonic untimed test gets none of them. Columns follow the test kind
(vlab.report.kind_rows.kind_of_data): a simple-shear test plots its shear force against the
amount of shear γ (plate travel / gap) and relaxes its shear stress."""

from __future__ import annotations

from pathlib import Path

from vlab.report import figures as plt  # pyplot-free Agg figures


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
        figures.append(Figure("hysteresis.png", "Load against grip extension over the whole protocol: "
                              "the area enclosed by a loop is the energy dissipated per cycle."))
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


def _finish(fig, ax, path: Path, title: str) -> None:
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    plt.save(fig, path)


def _hysteresis(datas: list[dict], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6.4, 4.4), dpi=120)
    x_col, f_col, _, xlabel = _axes(datas[0])
    for d in datas:
        c = d["curve"]
        x = [0.0] + c[x_col]
        ax.plot(x, [0.0] + c[f_col], "-", marker="o", ms=2, label=_label(d))
        ax.annotate("", xy=(x[2], c[f_col][1]), xytext=(x[1], c[f_col][0]),
                    arrowprops={"arrowstyle": "->", "color": "0.4"})
    ax.set_xlabel(xlabel)
    ax.set_ylabel("load-cell force [N]")
    ax.axhline(0, color="0.7", lw=0.5)
    _finish(fig, ax, path, f"{datas[0]['scene']['name']}: {_protocol(datas[0])['name']} loops")


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
