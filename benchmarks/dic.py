"""DIC benchmark: speed of a 1024² pair, the DIC Challenge 2.0 metrics, and (optionally) Pyvale
on the same images.

    NUMBA_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/dic.py [--pyvale /path/to/venv/bin/python]

Prints Markdown tables (copied into benchmarks/DIC.md). Images are rendered exactly from known
fields (vlab.dic.speckle); settings subset 31, step 10, strain window 5 unless said.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from vlab.dic import icgn, metrics, speckle
from vlab.dic.correlate import Correlator, Settings
from vlab.dic.images import write_grey

PYVALE_SCRIPT = r"""
import json, sys, time
import numpy as np
from pyvale import dic
folder = sys.argv[1]
out = {}
for name in ("shift", "strain"):
    t = time.perf_counter()
    dic.calculate_2d(reference=f"{folder}/ref.tif", deformed=f"{folder}/{name}.tif", roi_mask=np.asarray(
        json.load(open(f"{folder}/roi.json"))["mask"], bool), seed=[512, 512], subset_size=31, subset_step=10,
        num_threads=1, max_displacement=16, output_basepath=folder, output_prefix=f"pv_", print_level=0,
        precision=1e-4)
    out[name] = time.perf_counter() - t
print(json.dumps(out))
"""


def best_of(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - t)
    return min(times), value


def speed(pyvale: str | None) -> None:
    shape = (1024, 1024)
    pattern = speckle.make_pattern(shape, 4.0, 0.5, 0)
    t_render, ref = best_of(lambda: speckle.render(pattern, shape, None, 2), 1)
    shift = speckle.render(pattern, shape, speckle.translation(0.3, 0.6), 2)
    strained = speckle.render(pattern, shape, speckle.homogeneous(1e-3, -3e-4, (511.5, 511.5)), 2)
    settings = Settings()
    Correlator(ref, settings).correlate(shift)  # compile / load the kernel once
    print(f"\nRendering a 1024² image (2×2 sub-samples per pixel): {t_render:.2f} s\n")
    print("| 1024² pair, subset 31, step 10 | subsets | prepare s | correlate s | total s | converged |"
          " mean error u, v (px) | std u, v (px) | mean Exx, Eyy |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, image, fu, fv in (("shift (0.3, 0.6) px", shift, lambda x, y: 0.3, lambda x, y: 0.6),
                                ("strain 1e-3, -3e-4", strained, lambda x, y: 1e-3 * (x - 511.5),
                                 lambda x, y: -3e-4 * (y - 511.5))):
        tp, c = best_of(lambda: Correlator(ref, settings))
        tc, f = best_of(lambda: c.correlate(image))
        ok = f.status == icgn.OK
        eu, ev = f.u[ok] - fu(f.x[ok], f.y[ok]), f.v[ok] - fv(f.x[ok], f.y[ok])
        print(f"| {name} | {f.status.size} | {tp:.2f} | {tc:.2f} | {tp + tc:.2f} | {f.converged:.1%} | "
              f"{eu.mean():.1e}, {ev.mean():.1e} | {eu.std():.1e}, {ev.std():.1e} | "
              f"{np.nanmean(f.exx):.4e}, {np.nanmean(f.eyy):.4e} |")
    if pyvale:
        with tempfile.TemporaryDirectory() as tmp:
            for name, image in (("ref", ref), ("shift", shift), ("strain", strained)):
                write_grey(Path(tmp) / f"{name}.tif", image, 16)
            mask = np.zeros(shape, bool)
            mask[20:-20, 20:-20] = True
            (Path(tmp) / "roi.json").write_text(json.dumps({"mask": mask.tolist()}))
            (Path(tmp) / "run.py").write_text(PYVALE_SCRIPT)
            res = subprocess.run([pyvale, str(Path(tmp) / "run.py"), tmp], capture_output=True, text=True,
                                 env={"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "QT_QPA_PLATFORM": "offscreen",
                                      "MPLBACKEND": "Agg", "PATH": "/usr/bin:/bin"})
            if res.returncode:
                print("pyvale failed:", res.stderr[-2000:])
                return
            times = json.loads(res.stdout.strip().splitlines()[-1])
            import csv
            print("\n| Pyvale 2-D DIC, same images, 1 thread | subsets | seconds | mean error u, v (px) |"
                  " std u, v (px) |")
            print("|---|---|---|---|---|")
            for name, fu, fv in (("shift", lambda x, y: 0.3, lambda x, y: 0.6),
                                 ("strain", lambda x, y: 1e-3 * (x - 511.5), lambda x, y: -3e-4 * (y - 511.5))):
                with open(Path(tmp) / f"pv_{name}.csv") as fh:
                    rows = list(csv.DictReader(fh))
                x = np.array([float(r["subset_x"]) for r in rows])
                y = np.array([float(r["subset_y"]) for r in rows])
                eu = np.array([float(r["disp_u"]) for r in rows]) - fu(x, y)
                ev = np.array([float(r["disp_v"]) for r in rows]) - fv(x, y)
                print(f"| {name} | {len(rows)} | {times[name]:.2f} | {eu.mean():.1e}, {ev.mean():.1e} | "
                      f"{eu.std():.1e}, {ev.std():.1e} |")


def challenge() -> None:
    settings = Settings()
    cam = metrics.Camera(shape=(256, 256), noise=0.01)
    t = time.perf_counter()
    noise = metrics.noise_floor(settings, cam)
    bias0 = metrics.translation_bias(settings, metrics.Camera(shape=(256, 256), noise=0.0))
    bias1 = metrics.translation_bias(settings, cam)
    print("\n| shift (px) | bias u, v no noise (px) | std u, v no noise (px) | bias u, v 1 % noise (px) |"
          " std u, v 1 % noise (px) |")
    print("|---|---|---|---|---|")
    for a, b in zip(bias0["rows"], bias1["rows"]):
        print(f"| {a['shift_px']:.1f} | {a['bias_u_px']:+.1e}, {a['bias_v_px']:+.1e} | {a['std_u_px']:.1e}, "
              f"{a['std_v_px']:.1e} | {b['bias_u_px']:+.1e}, {b['bias_v_px']:+.1e} | {b['std_u_px']:.1e}, "
              f"{b['std_v_px']:.1e} |")
    res = metrics.spatial_resolution(settings, metrics.Camera(shape=(96, 1024), noise=0.0),
                                     (40, 60, 80, 100, 120, 140, 160, 200, 250, 300, 400, 500, 700, 1000))
    print("\n| period T (px) | displacement amplitude ratio | strain (Exy) amplitude ratio |")
    print("|---|---|---|")
    for r in res["rows"]:
        print(f"| {r['period_px']:.0f} | {r['displacement_ratio']:.4f} | {r['strain_ratio']:.4f} |")
    m = metrics.mei(noise, res)
    print("\n| metric (256² images, 4 px speckles, 1 % noise) | value |")
    print("|---|---|")
    print(f"| displacement noise floor σ_u, σ_v (px) | {noise['sigma_u_px']:.4f}, {noise['sigma_v_px']:.4f} |")
    print(f"| strain noise σ_Exx, σ_Eyy, σ_Exy (µε) | {noise['sigma_exx_microstrain']:.0f}, "
          f"{noise['sigma_eyy_microstrain']:.0f}, {noise['sigma_exy_microstrain']:.0f} |")
    print(f"| worst sub-pixel bias, no noise / 1 % (px) | {bias0['worst_bias_px']:.1e} / {bias1['worst_bias_px']:.1e} |")
    print(f"| displacement spatial resolution (10 % low) (px) | {_fmt(res['displacement_px'])} |")
    print(f"| strain spatial resolution (10 % low) (px) | {_fmt(res['strain_px'])} |")
    print(f"| MEI_u = σ_v · SR_u (px²) | {_fmt(m['displacement_px2'], '.3g')} |")
    print(f"| MEI_ε = σ_Exy · SR_ε² (px²) | {_fmt(m['strain_px2'], '.3g')} |")
    print(f"\n(metrics computed in {time.perf_counter() - t:.0f} s)")


def _fmt(v, spec=".0f"):
    return "not reached" if v is None else format(v, spec)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--pyvale", help="a Python interpreter with pyvale installed (its venv's bin/python)")
    ap.add_argument("--skip-speed", action="store_true")
    ap.add_argument("--skip-challenge", action="store_true")
    a = ap.parse_args()
    if not a.skip_speed:
        speed(a.pyvale)
    if not a.skip_challenge:
        challenge()
