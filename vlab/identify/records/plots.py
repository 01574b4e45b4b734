"""Figures of records (matplotlib, no physics): each record against the model with its band and
residuals; each raw export against its cleaned curve."""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["record_figures", "cleanup_figures"]


def _panel(ax, rax, obj, outcome, d):
    from vlab.identify import uncertainty as unc
    from vlab.identify.jacobian import value_and_jacobian
    from vlab.identify.records import KINDS
    from vlab.identify.records.fit import _floors

    y, g = value_and_jacobian(lambda X: obj.predict(X, d), outcome.x)
    band = unc.band(g, outcome.cov_x, outcome.tq)
    colour = "tab:orange" if d.role == "validate" else "tab:blue"
    rel = 100 * (y - d.y) / _floors(d)
    if d.kind == "dma":
        n = len(d.a)
        sym = "G" if d.extra["modulus"] == "shear" else "E"
        for j, (part, mark) in enumerate(((f"{sym}' storage", "o"), (f"{sym}'' loss", "s"))):
            sl = slice(j * n, (j + 1) * n)
            ax.loglog(d.a, d.y[sl], mark, color=colour, ms=4, label=f"{d.name}: {part}")
            ax.loglog(d.a, y[sl], "-", color="k", lw=1.1)
            ax.fill_between(d.a, y[sl] - band[sl], y[sl] + band[sl], color="k", alpha=0.18)
            rax.semilogx(d.a, rel[sl], mark + "-", color=colour, ms=3, lw=0.8)
        ax.set_ylabel("modulus (MPa)")
    else:
        ax.plot(d.a, d.y, "o", color=colour, ms=3, label=f"{d.name} ({d.kind}, {d.extra['test']})")
        ax.plot(d.a, y, "-", color="k", lw=1.1, label="fit")
        ax.fill_between(d.a, y - band, y + band, color="k", alpha=0.18, label="band (delta method)")
        rax.plot(d.a, rel, "o-", color=colour, ms=2, lw=0.8)
        ax.set_ylabel("nominal stress (MPa)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    rax.axhline(0, color="k", lw=0.6)
    rax.set_ylabel("residual (%)")
    rax.set_xlabel(KINDS[d.kind].XLABEL)
    rax.grid(alpha=0.3)


def _write_records(outcome, obj, records, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(records)
    fig, axes = plt.subplots(2, n, figsize=(4.6 * n, 6.0), squeeze=False, gridspec_kw={"height_ratios": [3, 1.3]})
    for j, d in enumerate(records):
        _panel(axes[0, j], axes[1, j], obj, outcome, d)
    fig.suptitle(f"{outcome.data['name']}: records", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def record_figures(outcome, obj, records):
    """([(file, caption)], [(file, writer)]) of the records' figure (none without records)."""
    if not records:
        return [], []
    caption = ("Records (points) against the model run over their own history (relaxation) or the Prony "
               "series' small-strain moduli (DMA), with the delta-method band; below: relative residuals.")
    return [("records.png", caption)], [("records.png", lambda p: _write_records(outcome, obj, records, p))]


def cleanup_figures(datasets, folder: Path) -> list[tuple[str, str]]:
    """cleanup.png (raw export against the cleaned curve, one panel per raw data set), written
    into folder; [] when no data set was cleaned."""
    raw = [d for d in datasets if d.extra and "cleanup" in d.extra]
    if not raw:
        return []
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(raw), figsize=(4.6 * len(raw), 4.0), squeeze=False)
    for ax, d in zip(axes[0], raw):
        rec = d.extra["cleanup"]
        ax.plot(rec["raw"]["stretch"], rec["raw"]["stress"], ".", color="0.6", ms=3,
                label="raw (F/A0 against 1 + u/L0)")
        ax.plot(d.a, d.y, "-", color="tab:blue", lw=1.4, label="cleaned: " + (", ".join(
            s["step"] + (f" ({s['method']})" if "method" in s else "") for s in rec["steps"]) or "units only"))
        ax.set_xlabel("stretch λ")
        ax.set_ylabel("nominal stress (MPa)")
        ax.set_title(d.name, fontsize=9)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(Path(folder) / "cleanup.png", dpi=110)
    plt.close(fig)
    return [("cleanup.png", "Raw machine export (grey) against the cleaned curve that was fitted; every step "
             "is in fit.json → datasets[].cleanup.")]
