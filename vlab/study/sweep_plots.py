"""The sweep page's chart: the first swept key against each measured quantity, from the run
summaries only (Agg backend, nothing recomputed).

One panel per quantity that at least one completed run measured (E, ν, final stress and force,
Newton iterations, wall time: the table's columns of those names, vlab.study.table.COLUMNS); in
each panel one line per value of the other swept keys (their combination, e.g. "mesh.order = 2,
mesh.cell = tet"). A numeric first key is drawn on a linear axis, or a logarithmic one where its
values span a factor of 20 or more (mesh sizes, tolerances); a non-numeric one (model names) at
evenly spaced positions in the grid's order. Failed and invalid runs have no point (the table
below the chart gives their diagnosis). A quantity whose values agree to FLAT_DIGITS significant
digits (the homogeneous block's E on every mesh: round-off) is drawn on a ±0.1 % axis and says so,
instead of magnifying the round-off into a curve.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

from vlab.report import figures as plt  # pyplot-free Agg figures

CHART_COLUMNS = ("E [MPa]", "nu", "final stress [MPa]", "final force [N]", "Newton iterations", "wall [s]")
LOG_SPAN = 20.0  # max/min of a positive numeric key from which its axis is logarithmic
FLAT_DIGITS = 6
TITLES = {"nu": "ν"}


def _number(value) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return None
    return float(value)


def swept_keys(summaries: list[dict]) -> list[str]:
    """The grid's keys in the order the grid gives them (each summary's label)."""
    return list(dict.fromkeys(k for s in summaries for k in (s.get("label") or {})))


def chart_quantities(summaries: list[dict]) -> list[tuple[str, tuple[str, ...]]]:
    """(header, path) of the chart's quantities that some completed run has a number for."""
    from vlab.study.table import COLUMNS, _get

    paths = dict(COLUMNS)
    ok = [s for s in summaries if s.get("status") == "ok"]
    return [(h, paths[h]) for h in CHART_COLUMNS if any(_number(_get(s, paths[h])) is not None for s in ok)]


def _positions(values: list) -> tuple[dict, list | None, bool]:
    """({value: x}, tick labels or None, logarithmic) of the first key's values."""
    numbers = [_number(v) for v in values]
    if all(n is not None for n in numbers):
        log = min(numbers) > 0 and max(numbers) / min(numbers) >= LOG_SPAN
        return {v: n for v, n in zip(values, numbers)}, None, log
    return {v: i for i, v in enumerate(values)}, [str(v) for v in values], False


def _flat_axis(ax, values: list[float]) -> None:
    """Values equal to FLAT_DIGITS digits: a ±0.1 % axis around them and a note (module docstring)."""
    lo, hi = min(values), max(values)
    mid = 0.5 * (lo + hi)
    if mid != 0 and hi - lo <= 10.0 ** -FLAT_DIGITS * abs(mid):
        ax.set_ylim(mid - 1e-3 * abs(mid), mid + 1e-3 * abs(mid))
        same = "" if lo == hi else f" to {FLAT_DIGITS} digits"
        ax.text(0.5, 0.08, f"all {mid:.{FLAT_DIGITS}g}{same}", transform=ax.transAxes,
                ha="center", fontsize=8, color="0.35")


def plot_sweep(summaries: list[dict], path: Path) -> list[dict] | None:
    """Draw the chart (module docstring) to ``path``; its panels (vlab.report.figures.describe), or
    None where there is nothing to draw (no swept key, or no completed run)."""
    with matplotlib.rc_context({"axes.formatter.useoffset": False}):  # 9.97594, not 1e−8 + 9.975936
        return _plot(summaries, path)


def _panel(ax, groups: dict, where: dict, x_key: str, others: list, header: str, q_path) -> None:
    """One quantity against the swept key: a line per group of the other keys' values (a group
    keeps its colour in every panel), flat when the values agree to round-off."""
    from vlab.study.table import _get

    drawn = []
    for i, (group, runs) in enumerate(groups.items()):
        points = sorted((where[(s.get("label") or {}).get(x_key)], _number(_get(s, q_path)))
                        for s in runs if s.get("status") == "ok" and _number(_get(s, q_path)) is not None)
        if not points:
            continue
        name = ", ".join(f"{k} = {v}" for k, v in zip(others, group)) or "runs"
        ax.plot([p[0] for p in points], [p[1] for p in points], "-o", ms=4, color=f"C{i % 10}", label=name)
        drawn += [p[1] for p in points]
    _flat_axis(ax, drawn)
    ax.set_title(TITLES.get(header, header), fontsize=10)
    ax.set_xlabel(x_key)
    ax.set_ylabel(TITLES.get(header, header))
    ax.grid(alpha=0.3)


def _plot(summaries: list[dict], path: Path) -> list[dict] | None:
    keys, quantities = swept_keys(summaries), chart_quantities(summaries)
    if not keys or not quantities:
        return None
    x_key, others = keys[0], keys[1:]
    x_values = list(dict.fromkeys((s.get("label") or {}).get(x_key) for s in summaries))
    where, ticks, log = _positions(x_values)
    groups: dict[tuple, list[dict]] = {}
    for s in summaries:
        label = s.get("label") or {}
        groups.setdefault(tuple(label.get(k) for k in others), []).append(s)
    cols = min(3, len(quantities))
    rows = -(-len(quantities) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.7 * cols, 3.5 * rows), dpi=110, squeeze=False)
    flat = [ax for row in axes for ax in row]
    for ax in flat[len(quantities):]:
        fig.delaxes(ax)
    for ax, (header, q_path) in zip(flat, quantities):
        _panel(ax, groups, where, x_key, others, header, q_path)
        if log:
            ax.set_xscale("log")
        if ticks is not None:
            ax.set_xticks(range(len(ticks)), ticks, rotation=20 if len(ticks) > 3 else 0)
    if others:
        flat[0].legend(fontsize=7, loc="best")
    fig.suptitle(f"{x_key} against each measured quantity" + (f"; a line per {', '.join(others)}" if others else ""),
                 fontsize=11)
    return plt.save(fig, path)
