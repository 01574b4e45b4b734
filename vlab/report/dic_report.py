"""A run's DIC in its report (scenes with ``[instruments.dic]``; vlab.pipeline.dic).

Files, in the model's folder (the report folder for one model):

    dic/images/level-KK.png   the camera's frames, 8- or 16-bit grey (level-00 the unloaded reference)
    dic/fields/level-KK.csv   the DIC of level KK against level-00, in ``vlab dic``'s columns
                              (vlab.dic.output.COLUMNS)
    dic/levels.csv            image,displacement,force: one row per fields CSV (image stem, grip
                              displacement (λ − 1) L₀ in mm, load-cell force in N)
    dic/dic.json              settings, camera (pixels, mm_per_px, centre, face, the pixel ↔ face
                              convention), per image the correlation summary and FE-vs-DIC levelled,
                              the noise floor, the virtual extensometer, timing, and
                              "source": what made the images (source_entry; `vlab dic` has none)
    dic/maps.png              the last level: DIC, levelled FE and their difference

results.json gets ``measured.dic`` (the virtual extensometer's E and ν beside the point
extensometers', with the relative differences) and ``dic`` (camera, noise floor, the DIC Challenge
2.0 metrics (``dic.metrics``, vlab.report.dic_metrics), levelled differences at the last level, timing).
"""

from __future__ import annotations

import csv
import html
import json
from pathlib import Path

import numpy as np

from vlab.dic.levelled import COMPONENTS


def stems(n_levels: int) -> list[str]:
    """level-00 (the reference) … level-KK, zero-padded to at least two digits."""
    width = max(2, len(str(n_levels)))
    return [f"level-{k:0{width}d}" for k in range(n_levels + 1)]


def _relative(a, b):
    return None if a is None or b is None or b == 0 else a / b - 1.0


def measured_dict(result) -> dict:
    """results.json's measured.dic: the DIC virtual extensometer beside the point extensometers."""
    run, const = result.dic, result.constants
    c = run.constants
    if c is None:
        return {"E": None, "nu": None, "note": run.gauge.get("note", "not a uniaxial test: no virtual extensometer")}
    return {"E": c.E, "nu": c.nu, "E_fit": c.E_fit, "nu_fit": c.nu_fit, "note": c.note,
            "E_difference": _relative(c.E, const.E), "nu_difference": _relative(c.nu, const.nu),
            "gauge_points": run.gauge["points"][-1] if run.gauge.get("points") else 0,
            "strain": "mean over the gauge area of sqrt(1 + 2 E_aa) - 1 (vlab.dic.extensometer)"}


def summary_dict(result) -> dict:
    """results.json's dic: camera, settings, noise floor, FE-vs-DIC levelled at the last level."""
    from vlab.dic.correlate import settings_dict
    from vlab.report.dic_metrics import metrics_dict

    run = result.dic
    rec = run.record
    return {"camera": rec.view.as_dict(), "settings": settings_dict(rec.view.settings),
            "levels": len(rec.fields), "noise_floor": rec.noise, "metrics": metrics_dict(rec),
            "levelled_last": run.differences[-1] if run.differences else None,
            "converged_last": rec.fields[-1].converged if rec.fields else None,
            "timing": run.timing, "folder": "dic"}


def write_folder(result_data: dict, run, folder: Path) -> list[str]:
    """dic/ in ``folder`` (module docstring); the files written, relative to ``folder``."""
    from vlab.dic import output
    from vlab.dic.images import write_grey

    rec, root = run.record, folder / "dic"
    (root / "images").mkdir(parents=True)
    (root / "fields").mkdir()
    names = stems(len(rec.fields))
    bits = rec.view.camera.bit_depth
    for name, image in zip(names, rec.images):
        write_grey(root / "images" / f"{name}.png", image, bits)
    images = {}
    for name, field, diff in zip(names[1:], rec.fields, run.differences):
        output.write_csv(root / "fields" / f"{name}.csv", field)
        images[name] = output.summary(field) | {"levelled_difference": diff}
    _write_levels(root / "levels.csv", names[1:], run)
    data = {"reference": names[0], "columns": list(output.COLUMNS), "images": images,
            "levels_csv": {"columns": ["image", "displacement", "force"], "units": {"displacement": "mm", "force": "N"},
                           "displacement": "grip displacement (lambda_grip - 1) L0, L0 the full specimen's grip separation"},
            "virtual_extensometer": result_data["measured"].get("dic"), "source": source_entry(result_data, rec.view)} | {
        k: v for k, v in result_data["dic"].items() if k in ("camera", "settings", "noise_floor", "metrics", "timing")}
    (root / "dic.json").write_text(json.dumps(_clean(data), indent=2), encoding="utf-8")
    files = ["dic/dic.json", "dic/levels.csv"]
    if rec.fields and run.levelled_last is not None:
        plot_maps(root / "maps.png", rec.fields[-1], run.levelled_last, names[-1], rec.view.camera.pitch)
        files.append("dic/maps.png")
    return files


def source_entry(result_data: dict, view) -> dict:
    """dic.json's "source": what made the images, for `vlab fit` to score its identification
    against (vlab.identify.field_truth). The scene's name, its [material] table as the scene gave it
    (a [compare.<label>] card or a --set override included), the small-strain moduli it implies
    (vlab.moduli.from_pair of the given pair, or of (μ0, K) for a card: E, ν, λ, μ, K, M in MPa,
    K = λ + 2μ/3) and the seeds of the camera's sensor noise and of the speckle."""
    scene, given = result_data["scene"], result_data["input"]
    moduli = {k: given[k] for k in ("E", "nu", "lambda", "mu", "K", "M")}
    return {"scene": scene["name"], "material": dict(scene["source"]["material"]),
            "moduli": moduli | {"units": {"E": "MPa", "nu": "1", "lambda": "MPa", "mu": "MPa", "K": "MPa", "M": "MPa"}},
            "seeds": {"camera": view.camera.seed, "speckle": view.speckle.seed},
            "note": "virtual images: vlab run rendered them from the FE solution of this material"}


def _clean(value):
    """JSON-safe: NaN and inf as None, numpy scalars as Python numbers."""
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, (np.floating, float)):
        return float(value) if np.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def _write_levels(path: Path, names: list[str], run) -> None:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(("image", "displacement", "force"))
        for name, d, f in zip(names, run.displacement, run.force):
            w.writerow((name, "" if d is None else f"{d:.12g}", f"{f:.12g}"))


def plot_maps(path: Path, field, fe: dict, name: str, pitch: float) -> None:
    """3 × 3 maps: rows Exx, Eyy, Exy; columns DIC, levelled FE (one colour scale per row) and
    DIC − FE; image axes in mm from the image's top-left pixel."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 3, figsize=(13, 7.5), constrained_layout=True)
    x, y = field.x * pitch, field.y * pitch
    extent = (x.min(), x.max(), y.max(), y.min())
    for row, comp in zip(axes, COMPONENTS):
        dic, model = getattr(field, comp), fe[comp]
        both = np.concatenate([dic[np.isfinite(dic)], model[np.isfinite(model)]])
        lo, hi = (np.percentile(both, [1, 99]) if both.size else (0.0, 1.0))
        for ax, data, title, lim in ((row[0], dic, f"DIC {comp}", (lo, hi)), (row[1], model, f"FE levelled {comp}", (lo, hi)),
                                     (row[2], dic - model, f"DIC − FE {comp}", None)):
            if lim is None:  # the difference: a symmetric scale, 0 white
                d = np.abs(data[np.isfinite(data)])
                top = float(np.percentile(d, 99)) if d.size else 1.0
                lim = (-top, top)
            kw = {"vmin": lim[0], "vmax": lim[1], "cmap": "viridis" if title.startswith(("DIC ", "FE")) and "−" not in title
                  else "coolwarm"}
            im = ax.imshow(np.ma.masked_invalid(data), extent=extent, interpolation="nearest", **kw)
            ax.set_title(title, fontsize=10)
            ax.set_xlabel("x (mm)")
            ax.set_ylabel("y (mm, down)")
            fig.colorbar(im, ax=ax, shrink=0.8).formatter.set_useOffset(False)
    fig.suptitle(f"{name}: DIC against the FE field passed through the same subset and strain window")
    fig.savefig(path, dpi=80)
    plt.close(fig)


def _pct(v) -> str:
    return "—" if v is None else f"{100 * v:+.2f} %"


def _g(v, digits: int = 5) -> str:
    return "—" if v is None else f"{v:.{digits}g}"


def html_section(data: dict, prefix: str = "", image_source=None) -> str:
    """The run page's DIC section from a results dict (``prefix``: the model's folder, "" for one;
    ``image_source(name)``: the img src of a file of the folder, e.g. inlined; default its name)."""
    from vlab.report.dic_metrics import metrics_table

    d, m, point = data["dic"], data["measured"].get("dic") or {}, data["measured"]
    cam, lev = d["camera"], d.get("levelled_last") or {}
    rows = [("E (MPa)", point.get("E"), m.get("E"), m.get("E_difference")),
            ("ν", point.get("nu"), m.get("nu"), m.get("nu_difference"))]
    table = "".join(f"<tr><th>{n}</th><td class=num>{_g(a)}</td><td class=num>{_g(b)}</td><td class=num>{_pct(c)}</td></tr>"
                    for n, a, b, c in rows)
    levelled = "".join(f"<tr><th>{c}</th><td class=num>{_g((lev.get(c) or {}).get('rms'), 3)}</td>"
                       f"<td class=num>{_g((lev.get(c) or {}).get('max'), 3)}</td></tr>" for c in COMPONENTS + ("u_px", "v_px"))
    maps = image_source(f"{prefix}dic/maps.png") if image_source else html.escape(f"{prefix}dic/maps.png")
    face = cam["face"]
    return f"""<h2>Digital image correlation (virtual camera)</h2>
<p>Camera {cam['pixels'][0]} × {cam['pixels'][1]} px at {cam['mm_per_px']:.4g} mm/px, {cam['bit_depth']}-bit,
noise {cam['noise']:g} of full scale, blur σ {cam['blur']:g} px, looking at the {html.escape(face['name'])} face
(x₁ along {face['e1']}, x₂ along {face['e2']}); subset {d['settings']['subset']} px, step {d['settings']['step']} px,
strain window {d['settings']['strain_window']} points; {d['levels']} levels correlated against the reference
(images, fields and levels.csv in <a href="{html.escape(prefix)}dic/dic.json">dic/</a>).</p>
<table><tr><th></th><th>point extensometers</th><th>DIC virtual extensometer</th><th>difference</th></tr>{table}</table>
<p><small>{html.escape(str(m.get('strain') or m.get('note') or ''))}; same modulus window and fit as the point extensometers.</small></p>
{metrics_table(d['metrics']) if 'metrics' in d else ''}
<table><tr><th>DIC − levelled FE, last level</th><th>rms</th><th>max</th></tr>{levelled}</table>
<figure><img src="{maps}" alt="DIC maps"><figcaption>Last level: DIC, the FE field levelled through the same
subset grid and strain window, and their difference (measurement error, not filtering).</figcaption></figure>"""
