"""Figures without pyplot: a matplotlib Figure on its own Agg canvas.

The report only draws PNGs; pyplot's state machine and backend selection are not needed, and
importing matplotlib.pyplot costs ~3× matplotlib.figure + the Agg backend (python -X importtime on
the benchmark machine). ``subplots`` takes pyplot.subplots' common arguments; a figure is freed
with its last reference (there is no pyplot registry to ``close`` it from).
"""

from __future__ import annotations

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure


def subplots(nrows: int = 1, ncols: int = 1, *, figsize=None, dpi=None, **kwargs):
    """(figure, axes) as pyplot.subplots(nrows, ncols, figsize=, dpi=, squeeze=, sharex=, …)."""
    fig = Figure(figsize=figsize, dpi=dpi)
    FigureCanvasAgg(fig)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def describe(fig: Figure) -> list[dict]:
    """What each panel of ``fig`` shows, for tests and callers that check a figure: per axes (insets
    excluded) its title, axis labels, x scale, number of data lines (axhline/axvline references, drawn in
    axes coordinates on one axis, are not counted), their colours and the legend entries."""
    panels = []
    for ax in fig.axes:
        legend = ax.get_legend()
        lines = [ln for ln in ax.get_lines() if ln.get_transform() == ax.transData]
        panels.append({"title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
                       "xscale": ax.get_xscale(),
                       "lines": len(lines), "colours": [ln.get_color() for ln in lines],
                       "legend": [t.get_text() for t in legend.get_texts()] if legend else []})
    return panels


def save(fig: Figure, path) -> list[dict]:
    """Lay the figure out (tight_layout), write the PNG, free the figure; returns :func:`describe`.

    The layout engine that tight_layout leaves set is dropped before saving: with one set,
    savefig draws the whole figure once more, without rendering, before the real draw (the
    layout would be recomputed from it); the laid-out figure needs no second layout. The PNG is
    byte-identical and the save ~15 % faster (benchmarks/RESULTS.md, "command overhead")."""
    fig.tight_layout()
    fig.set_layout_engine(None)
    fig.savefig(path)
    panels = describe(fig)
    close(fig)
    return panels


def close(fig: Figure) -> None:
    """Drop the figure's artists now (its memory goes with its last reference)."""
    fig.clear()
