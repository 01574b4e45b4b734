"""The budget's folder: budget.json, samples.csv, tornado_E.png, tornado_nu.png,
tornado_E_crosshead.png, histogram.png, index.html (through vlab.report.folder: atomic, never over a
folder vlab did not make)."""

from __future__ import annotations

import csv
import html
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from vlab.report.folder import report_folder  # noqa: E402
from vlab.uncertainty.budget import QUANTITIES  # noqa: E402

__all__ = ["write_budget"]

_LABEL = {"E": "E (MPa)", "nu": "ν", "E_crosshead": "E, crosshead (MPa)"}


def _tornado(q: dict, path: Path) -> None:
    rows = [r for r in q["contributions"] if r["u_contribution"] is not None][::-1]
    fig, ax = plt.subplots(figsize=(7, 0.45 * len(rows) + 1.4))
    y = np.arange(len(rows))
    signed = [r["sensitivity"] * r["u_input"] for r in rows]
    ax.barh(y, signed, color=["tab:blue" if v >= 0 else "tab:red" for v in signed], height=0.6,
            label="GUM: c_i · u_i (sign: + raises the result)")
    sob = [np.sqrt(max(r["sobol"], 0.0)) * q["u"] if r["sobol"] is not None else 0.0 for r in rows]
    ax.plot(sob, y, "k|", ms=14, mew=2, label="Monte Carlo: √S_i · u (first-order Sobol)")
    ax.plot([-s for s in sob], y, "k|", ms=14, mew=2)
    ax.axvline(0, color="k", lw=0.8)
    ax.set_yticks(y, [r["input"] for r in rows], fontsize=8)
    ax.set_xlabel(f"change of {_LABEL[q['quantity']]} for one standard uncertainty of the input")
    ax.set_title(f"{_LABEL[q['quantity']]}: nominal {q['nominal']:.6g}, u_GUM {q['gum']['u']:.3g}, "
                 f"u_MC {q['u']:.3g}", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _histogram(budget: dict, runs, path: Path) -> None:
    fig, axes = plt.subplots(1, len(QUANTITIES), figsize=(14, 3.6))
    for ax, name in zip(axes, QUANTITIES):
        q = budget.get(name)
        y = np.array([v for v in getattr(runs, name) if v is not None], float)
        if q is None or not len(y):
            ax.set_visible(False)
            continue
        ax.hist(y, bins=max(8, int(np.sqrt(len(y)))), density=True, color="tab:blue", alpha=0.6,
                label=f"{len(y)} virtual tests")
        g = np.linspace(y.min() - q["u"], y.max() + q["u"], 200)
        ug = q["gum"]["u"]
        if ug > 0:
            ax.plot(g, np.exp(-0.5 * ((g - q["nominal"]) / ug) ** 2) / (ug * np.sqrt(2 * np.pi)), "k-", lw=1.2,
                    label="GUM: normal(nominal, u_c)")
        for v, style in ((q["mean"] - q["U"], ":"), (q["mean"], "-"), (q["mean"] + q["U"], ":")):
            ax.axvline(v, color="tab:red", ls=style, lw=1)
        ax.set_xlabel(_LABEL[name])
        ax.set_title(f"mean {q['mean']:.5g} ± U {q['U']:.3g} (k = 2)", fontsize=9)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _samples_csv(path: Path, spec, runs) -> None:
    names = [s.name for s in spec.sources]
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["sample", *names, "status", "E_run", "nu_run", "E_crosshead_run", "E", "nu", "E_crosshead",
                    "percent_bending", "cache_hit"])
        for i, (d, s, E, nu, Ec) in enumerate(zip(runs.deltas, runs.summaries, runs.E, runs.nu, runs.E_crosshead)):
            m = s.get("measured") or {}
            w.writerow([i, *[repr(d[n]) for n in names], s["status"], m.get("E"), m.get("nu"), m.get("E_crosshead"),
                        E, nu, Ec, m.get("percent_bending"), s.get("cache_hit")])


def _f(v, digits=4) -> str:
    return "—" if v is None else f"{v:.{digits}g}" if isinstance(v, float) else html.escape(str(v))


def _table(q: dict) -> str:
    head = "<tr><th>input</th><th>u of the input</th><th>source</th><th>sensitivity</th><th>u contribution</th>" \
           "<th>GUM share</th><th>Sobol S₁ ± error</th></tr>"
    body = "".join(
        f"<tr><td>{html.escape(r['input'])}</td><td>{_f(r['u_input'])} {html.escape(r['unit'])} "
        f"({r['distribution']})</td><td>{html.escape(r['source'])}</td><td>{_f(r['sensitivity'])}</td>"
        f"<td>{_f(r['u_contribution'])}</td><td>{_f(None if r['share'] is None else 100 * r['share'], 3)} %</td>"
        f"<td>{_f(r['sobol'], 3)} ± {_f(r['sobol_error'], 2)}</td></tr>" for r in q["contributions"])
    return f"<table>{head}{body}</table>"


def _section(q: dict | None, name: str) -> str:
    if q is None:
        return f"<h2>{name}</h2><p>not measured by this test</p>"
    se = q["statistical_error"]
    return (f"<h2>{_LABEL[name]}</h2><p>Monte Carlo: <b>{q['mean']:.6g} ± {q['U']:.3g}</b> (U, k = 2; u = "
            f"{q['u']:.4g}; 95 % of the samples in [{q['quantiles']['2.5%']:.6g}, {q['quantiles']['97.5%']:.6g}]). "
            f"Statistical error of the Monte Carlo: mean ± {_f(se['mean'], 2)}, u ± "
            f"{_f(None if se['u_relative'] is None else 100 * se['u_relative'], 2)} %. Linearised GUM: u_c = "
            f"{q['gum']['u']:.4g} (u_GUM / u_MC = {_f(q['gum_over_monte_carlo'])}).</p>"
            f"<figure><img src='tornado_{name}.png' alt='tornado chart of {name}'></figure>{_table(q)}")


def _bending(pb: dict | None) -> str:
    """The ASTM E1012 percent bending of a budget with alignment inputs: the nominal run's and the
    samples' mean, u and largest |B|, four gauges and each plane's signed pair (budget.json)."""
    if not pb:
        return ""
    rows = [("four gauges, √(b_y² + b_z²)/a", pb), ("thickness plane (top − bottom), signed", pb["thickness_plane"]),
            ("width plane (y₁ − y₀), signed", pb["width_plane"])]
    body = "".join(f"<tr><td>{label}</td><td>{_f(r['nominal'])}</td><td>{_f(r['mean'])}</td><td>{_f(r['u'])}</td>"
                   f"<td>{_f(r['max_abs'])}</td></tr>" for label, r in rows)
    return ("<h2>Alignment: ASTM E1012 percent bending at the gauge centre (%)</h2><table><tr><th>B</th>"
            "<th>nominal run</th><th>samples' mean</th><th>u</th><th>largest |B|</th></tr>"
            f"{body}</table><p>Strain gauges on the four faces at the extensometer's centre, read at the last "
            "level in the modulus window; every sample's misalignment drawn (vlab.measure.bending).</p>")


def page(budget: dict) -> str:
    from vlab.report.html import _STYLE

    inputs = "".join(f"<li>{html.escape(i['input'])}: {i['distribution']}, half-width {_f(i['half_width'])} "
                     f"{html.escape(i['unit'])} ({html.escape(i['source'])})</li>" for i in budget["inputs"])
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>vlab budget — {html.escape(budget['scene'])}"
            f"</title><style>{_STYLE}</style></head><body><h1>{html.escape(budget['scene'])}: uncertainty budget</h1>"
            f"<p>{budget['samples']} virtual tests ({budget['failed_samples']} failed), each with every input drawn; "
            f"{budget['runs']['paired']} paired runs for the GUM sensitivities. Resolution of the readings: "
            f"{html.escape(json.dumps(budget['resolution']) or 'none')}.</p><ul>{inputs}</ul>"
            "<figure><img src='histogram.png' alt='histograms of E, nu and the crosshead E'><figcaption>Monte Carlo distribution; "
            "red: mean and mean ± U; black: the GUM's normal distribution around the nominal value."
            f"</figcaption></figure>{_bending(budget.get('percent_bending'))}"
            f"{''.join(_section(budget.get(name), name) for name in QUANTITIES)}"
            "<p>Files: budget.json, samples.csv (every sample's deviations, runs and results).</p></body></html>")


def write_budget(dest, budget: dict, spec, runs, scene_text: str) -> Path:
    """Write the folder; returns its index.html."""
    with report_folder(dest, "budget") as tmp:
        (tmp / "budget.json").write_text(json.dumps(budget, indent=2), encoding="utf-8")
        _samples_csv(tmp / "samples.csv", spec, runs)
        for name in QUANTITIES:
            if budget.get(name):
                _tornado(budget[name], tmp / f"tornado_{name}.png")
        _histogram(budget, runs, tmp / "histogram.png")
        (tmp / "scene.toml").write_text(scene_text, encoding="utf-8")
        (tmp / "index.html").write_text(page(budget), encoding="utf-8")
    return Path(dest.path) / "index.html"
