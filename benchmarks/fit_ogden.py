"""Benchmark: a 3-term Ogden fitted to three data sets of 20 points each from 20 starts.

    python -m benchmarks.fit_ogden [--repeat 5]

Data: the Ogden-3 card fitted to Treloar 1944 (specimens/treloar1944/treloar-all.toml), evaluated
at 20 stretches per mode (uniaxial 1.1..7, equibiaxial 1.1..4.5, planar 1.1..5) with 1 % relative
Gaussian noise (seed 0). Reports wall and CPU time of the whole multi-start fit (median of the
repeats), the residual and Jacobian evaluations, and how many starts reached the best objective.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from vlab.identify.datasets import Dataset
from vlab.identify.fitfile import FitSpec
from vlab.identify.fitting import fit_homogeneous
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, response

CARD = [0.0383062, 0.299489, 0.000281673, -1.39983, 1.80752, 6.19258]
GRIDS = {"uniaxial": (1.1, 7.0), "equibiaxial": (1.1, 4.5), "planar": (1.1, 5.0)}


def datasets(model, noise=0.01, seed=0):
    rng = np.random.default_rng(seed)
    out = []
    for kind, (lo, hi) in GRIDS.items():
        a = np.linspace(lo, hi, 20)
        y = np.real(response(model, np.array([CARD]), kind, a))[0] * (1 + noise * rng.standard_normal(20))
        out.append(Dataset(kind, kind, kind, "fit", 1.0, "nominal", a, None, y))
    return tuple(out)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    model = Constitutive(law_for("ogden", 3))
    spec = FitSpec("bench", model, datasets(model), starts=20, seed=0)
    fit_homogeneous(spec)  # warm-up (imports, first calls)
    walls, cpus = [], []
    for _ in range(args.repeat):
        w, c = time.perf_counter(), time.process_time()
        out = fit_homogeneous(spec)
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    d = out.data
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())} on {os.cpu_count()} cores")
    print(f"Ogden-3, 3 x 20 points, 20 starts: wall {np.median(walls):.3f} s (min {min(walls):.3f}), "
          f"CPU {np.median(cpus):.3f} s (min {min(cpus):.3f}); median of {args.repeat}")
    print(f"  fit only (multi-start): {d['timing']['fit_s']:.3f} s; evaluations {d['starts']['evaluations']}; "
          f"starts at the best objective {d['starts']['reached_best']} of 20")
    rms = ", ".join(f"{x['rms_relative']:.4f}" for x in d["datasets"])
    print(f"  rms relative per set: {rms}")


if __name__ == "__main__":
    main()
