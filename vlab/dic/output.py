"""What a DIC analysis writes: fields/<stem>.csv, dic.json, maps and index.html (vlab dic).

CSV columns: x_px, y_px (subset centre in the reference image: x right, y down), u_px, v_px
(its displacement), exx, eyy, exy (Green–Lagrange, strain window), zncc, iterations, status
(ok | no texture | left the image | did not converge | low correlation). u, v and the strains are
empty where the subset failed — never a made-up value.
"""

from __future__ import annotations

import csv
import html
import json
from pathlib import Path

import numpy as np

from vlab.dic import icgn

COLUMNS = ("x_px", "y_px", "u_px", "v_px", "exx", "eyy", "exy", "zncc", "iterations", "status")


def _num(value: float, digits: int = 10) -> str:
    return "" if not np.isfinite(value) else f"{value:.{digits}g}"


def write_csv(path: Path, field) -> None:
    """One row per subset, row by row of the grid."""
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(COLUMNS)
        for k in range(field.x.size):
            i, j = np.unravel_index(k, field.x.shape)
            st = int(field.status[i, j])
            w.writerow([int(field.x[i, j]), int(field.y[i, j]), _num(field.u[i, j]), _num(field.v[i, j]),
                        _num(field.exx[i, j]), _num(field.eyy[i, j]), _num(field.exy[i, j]),
                        _num(field.zncc[i, j], 8), int(field.iterations[i, j]), icgn.STATUS[st]])


def summary(field) -> dict:
    """Per image: the share converged, the counts by status, the ZNCC and the mean strains."""
    ok = field.status == icgn.OK
    z = field.zncc[ok]

    def mean(a):
        a = a[np.isfinite(a)]
        return float(a.mean()) if a.size else None

    return {"subsets": int(field.status.size), "converged_share": field.converged, "status": field.counts(),
            "zncc_mean": float(z.mean()) if z.size else None, "zncc_min": float(z.min()) if z.size else None,
            "iterations_mean": float(field.iterations[ok].mean()) if ok.any() else None,
            "mean_exx": mean(field.exx), "mean_eyy": mean(field.eyy), "mean_exy": mean(field.exy)}


def plot_maps(path: Path, field, title: str) -> None:
    """u, v, exx, eyy, exy and ZNCC over the reference image (image axes: y down)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = (("u (px)", field.u), ("v (px)", field.v), ("Exx", field.exx), ("Eyy", field.eyy),
              ("Exy", field.exy), ("ZNCC", np.where(field.status == icgn.OK, field.zncc, np.nan)))
    fig, axes = plt.subplots(2, 3, figsize=(12, 7), constrained_layout=True)
    extent = (field.x.min(), field.x.max(), field.y.max(), field.y.min())
    for ax, (name, data) in zip(axes.ravel(), panels):
        finite = np.isfinite(data)
        im = ax.imshow(np.ma.masked_invalid(data), extent=extent, cmap="viridis", interpolation="nearest")
        ax.set_title(name if finite.any() else f"{name}: no valid subset")
        ax.set_xlabel("x (px)")
        ax.set_ylabel("y (px)")
        bar = fig.colorbar(im, ax=ax, shrink=0.8)
        bar.formatter.set_useOffset(False)  # ZNCC near 1 read as "1e-6 + 9.9999e-1" with an offset
        bar.update_ticks()
    fig.suptitle(title)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write_index(path: Path, data: dict) -> None:
    rows = "".join(
        f"<tr><td>{html.escape(name)}</td><td>{s['converged_share']:.1%}</td>"
        f"<td>{'' if s['zncc_mean'] is None else format(s['zncc_mean'], '.5f')}</td>"
        f"<td>{html.escape(', '.join(f'{k}: {v}' for k, v in s['status'].items() if v))}</td>"
        f"<td>{'' if s['mean_exx'] is None else format(s['mean_exx'], '.3e')}</td>"
        f"<td>{'' if s['mean_eyy'] is None else format(s['mean_eyy'], '.3e')}</td></tr>"
        for name, s in data["images"].items())
    figures = "".join(f"<h2>{html.escape(name)}</h2><img src='maps/{html.escape(name)}.png' style='max-width:100%'>"
                      for name in data["images"])
    settings = html.escape(json.dumps(data["settings"], indent=1))
    path.write_text(f"""<!doctype html><html><head><meta charset="utf-8"><title>vlab dic</title>
<style>body{{font-family:sans-serif;max-width:1200px;margin:auto}}td,th{{padding:2px 8px;border-bottom:1px solid #ddd}}</style>
</head><body><h1>DIC: {html.escape(data['reference'])}</h1>
<p>Subset-based 2-D DIC (IC-GN, affine shape function, bicubic B-spline interpolation); strains are
Green–Lagrange from the strain window, in image axes (x right, y down). Fields: fields/&lt;image&gt;.csv.</p>
<table><tr><th>image</th><th>converged</th><th>mean ZNCC</th><th>subsets by status</th><th>mean Exx</th>
<th>mean Eyy</th></tr>{rows}</table>
<h2>Settings</h2><pre>{settings}</pre>{figures}
<p>Time: {data['timing']['total_s']:.3g} s.</p></body></html>""", encoding="utf-8")
