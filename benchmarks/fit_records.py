"""Benchmark: Prony series fitted back from synthetic lab records, seed after seed.

    python -m benchmarks.fit_records [--seeds 20] [--starts 4]

Records from vlab's own forward model (vlab.identify.records.prony; specimens/records/make_records.py)
with known constants and 0.5 % relative Gaussian noise, one seed each:
- relaxation: Neo-Hookean μ = 0.6 MPa + two Prony terms (β = 0.5, 0.3; τ = 1, 10 s), uniaxial
  ramp to λ = 1.5 in 1 s (10 steps) and a 50 s hold (20 geometric steps);
- DMA: tensile E', E'' of μ = 0.6 MPa + three terms (β = 0.4, 0.3, 0.2; τ = 0.05, 0.5, 5 s),
  31 frequencies over 3 decades (0.01–10 Hz);
- cycles: Neo-Hookean μ = 0.6 MPa + Ogden–Roxburgh r = 2, m = 0.3 MPa, β = 0.1, three uniaxial
  loading–unloading cycles to λ = 1.5, 2, 2.5 (stretch steps 0.05, 90 points).
Prints, per record, the fraction of (seed, constant) pairs whose fitted value lies within two
reported standard errors of the truth (≈ 95 % expected), the fraction of seeds with every
constant inside, and the CPU and wall time of a whole fit (starts + uncertainty), median.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from vlab.identify.fitfile import FitSpec
from vlab.identify.fitting import fit_any
from vlab.identify.records.prony import PronySpec
from vlab.identify.records.softening import MullinsSpec
from specimens.records.make_records import NH, cycles, dma, relaxation  # noqa: E402
from vlab.identify.datasets import Dataset

CASES = {
    "relaxation (NH + 2 Prony terms)": {"mu": 0.6, "beta": [0.5, 0.3], "tau": [1.0, 10.0]},
    "DMA (NH + 3 Prony terms, 3 decades)": {"mu": 0.6, "beta": [0.4, 0.3, 0.2], "tau": [0.05, 0.5, 5.0]},
    "cycles (NH + Ogden–Roxburgh, 3 cycles)": {"mu": 0.6, "r": 2.0, "m": 0.3, "mullins_beta": 0.1},
}


def record(case: str, rng):
    """(data set, the effects fitted)."""
    if case.startswith("relaxation"):
        t, lam, P = relaxation(rng)
        d = Dataset("relax", "", "relaxation", "fit", 1.0, "nominal", t, lam, P, extra={"test": "uniaxial"})
        return d, {"viscoelastic": PronySpec(2)}
    if case.startswith("cycles"):
        lam, P = cycles(rng)
        extra = {"test": "uniaxial", "stretch": lam, "time": None, "mask": np.ones(len(lam), bool), "branch": "all"}
        return Dataset("cycles", "", "cyclic", "fit", 1.0, "nominal", lam, None, P, extra=extra), {"mullins": MullinsSpec()}
    f, s, l = dma(rng)
    d = Dataset("dma", "", "dma", "fit", 1.0, "nominal", f, None, np.r_[s, l], extra={"modulus": "tensile"})
    return d, {"viscoelastic": PronySpec(3)}


def run(case: str, seeds: int, starts: int):
    truth = CASES[case]
    inside, all_in, cpu, wall = [], [], [], []
    for seed in range(seeds):
        d, effects = record(case, np.random.default_rng(1000 + seed))
        spec = FitSpec("bench", NH, (d,), starts=starts, seed=seed, effects=effects)
        c0, w0 = time.process_time(), time.perf_counter()
        out = fit_any(spec)
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
        p, u = out.data["parameters"], out.data["uncertainty"]
        hits = []
        for k, v in truth.items():
            for i, vi in enumerate(np.atleast_1d(v)):
                key = f"{k}[{i}]" if isinstance(v, list) else k
                hits.append(abs(np.atleast_1d(p[k])[i] - vi) <= 2 * u[key]["standard_error"])
        inside += hits
        all_in.append(all(hits))
    return np.mean(inside), np.mean(all_in), np.median(cpu), np.median(wall), len(inside)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--starts", type=int, default=4)
    a = ap.parse_args()
    print(f"load average {' / '.join(f'{x:.2f}' for x in os.getloadavg())}; {a.seeds} seeds, {a.starts} starts, "
          "0.5 % noise")
    print(f"{'record':<38} {'within 2 SE':>12} {'seeds all in':>13} {'CPU s':>7} {'wall s':>7}")
    for case in CASES:
        frac, all_in, cpu, wall, n = run(case, a.seeds, a.starts)
        print(f"{case:<38} {100 * frac:>10.1f} % {100 * all_in:>11.1f} % {cpu:>7.3f} {wall:>7.3f}   ({n} pairs)")


if __name__ == "__main__":
    main()
