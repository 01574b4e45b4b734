"""Benchmark: FE-in-the-loop `vlab design` — predicted standard errors against the scatter of real
FE-in-the-loop fits.

    python -m benchmarks.design_fe_scatter [--case block|dumbbell] [--seeds 50] [--noise 0.01]

A Mooney–Rivlin specimen (C10 = 0.2, C01 = 0.05 MPa fitted, K = 4 MPa held) is pulled once at the
true card; its readings are the spline of the load-cell force at 20 extensometer strains evenly
spaced over [0.05, 0.95 × the end strain] (what vlab.identify.fe_design plans), with relative
Gaussian noise F (1 + σ z) for seeds 0..N−1. Each noisy curve is fitted by `vlab fit`'s FE in the
loop (vlab.identify.fe_loop.fit_specimen, start 1.3× the true card, relative residuals). The
standard deviation of each fitted constant over the seeds is compared with the standard error
vlab.identify.fe_design predicts at the true card with s = σ. With N seeds a sample standard
deviation has a relative standard error of about 1/√(2(N − 1)) (10 % at N = 50), printed beside
the ratio.

Cases: ``block`` — a clamped block 12 × 4 × 4 mm (hexahedra, mesh 2 mm: its ends are held, so the
state is not homogeneous), grip stretch 1.6 in 8 steps; ``dumbbell`` — the ISO 37 type 2 dumb-bell
of benchmarks/fit_fe_dogbone.py (hexahedra, mesh 2 mm, 1161 DOFs), grip stretch 1.6 in 8 steps.
"""

from __future__ import annotations

import argparse
import dataclasses
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

SPECIMENS = {
    "block": '[specimen]\nshape = "block"\nsize = [12.0, 4.0, 4.0]\n[mesh]\nsize = 2.0\norder = 1\ncell = "hex"\n'
             '[test]\nkind = "uniaxial"\ngrips = "clamped"\nstretch = 2.2\nsteps = 12\n',
    "dumbbell": '[specimen]\nshape = "dogbone"\nstandard = "ISO 37 2"\n[mesh]\nsize = 2.0\norder = 1\ncell = "hex"\n'
                '[test]\nkind = "uniaxial"\nstretch = 1.6\nsteps = 8\n',
}
TRUE = {"C10": 0.2, "C01": 0.05}
HELD = {"K": 4.0}
NAMES = ("C10", "C01")


def scene_text(case: str) -> str:
    card = "".join(f"{k} = {v!r}\n" for k, v in (TRUE | HELD).items())
    return f'name = "design-{case}"\n[material]\nmodel = "mooney-rivlin"\n{card}' + SPECIMENS[case]


def run(case: str, seeds: int, noise: float) -> dict:
    from vlab.identify.datasets import Dataset
    from vlab.identify.design import assess
    from vlab.identify.fe_design import SpecimenTest, specimen_rows
    from vlab.identify.fe_loop import fit_specimen, residuals
    from vlab.identify.fe_sensitivity import simulate
    from vlab.identify.fitfile import load_fit

    folder = Path(tempfile.mkdtemp(prefix="design-fe-"))
    text = scene_text(case)
    (folder / "scene.toml").write_text(text)
    fe = {"scene_path": str(folder / "scene.toml"), "scene_raw": tomllib.loads(text), "parameters": NAMES,
          "model": "mooney-rivlin", "volumetric": None}
    t0 = time.perf_counter()
    sim = simulate(fe, TRUE | HELD)
    test = SpecimenTest(fe["scene_path"], case, "uniaxial", case, 0.0, 0.05, 0.95 * float(sim.strain[-1, 0]), 20)
    predicted = assess(specimen_rows(sim, test, True), noise, [TRUE[n] for n in NAMES], NAMES)
    t_design = time.perf_counter() - t0
    e = np.linspace(test.lo, test.hi, test.points)
    d = Dataset("truth", "", "specimen", "fit", 1.0, "nominal", e, None, np.ones_like(e))
    _, _, force = residuals(sim, d, False)
    (folder / "fit.toml").write_text(
        '[model]\nname = "mooney-rivlin"\n[[data]]\nfile = "r.csv"\nkind = "specimen"\n[fe]\nscene = "scene.toml"\n'
        f'parameters = ["C10", "C01"]\nstart = {{ C10 = {1.3 * TRUE["C10"]!r}, C01 = {1.3 * TRUE["C01"]!r} }}\n'
        "max_solves = 30\ncache = false\n")
    fitted, solves, failed = [], [], 0
    t1 = time.perf_counter()
    for seed in range(seeds):
        y = force * (1 + noise * np.random.default_rng(seed).standard_normal(len(force)))
        (folder / "r.csv").write_text("strain,force\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(e, y)))
        out = fit_specimen(load_fit(folder / "fit.toml"))
        if not out.converged:
            failed += 1
            continue
        fitted.append([out.data["parameters"][n] for n in NAMES])
        solves.append(out.data["fe"]["solves"])
    t_fits = time.perf_counter() - t1
    fitted = np.array(fitted)
    scatter = fitted.std(axis=0, ddof=1)
    return {"case": case, "dofs": sim.dofs, "seeds": seeds, "converged": len(fitted), "failed": failed,
            "mean_solves": float(np.mean(solves)), "design_s": t_design, "fits_s": t_fits,
            "verdict": predicted["verdict"], "correlation": predicted["correlation"]["matrix"][0][1],
            "rows": [(n, predicted["standard_errors"][n], float(scatter[i]), float(fitted[:, i].mean()))
                     for i, n in enumerate(NAMES)]}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", choices=sorted(SPECIMENS), default="block")
    ap.add_argument("--seeds", type=int, default=50)
    ap.add_argument("--noise", type=float, default=0.01)
    a = ap.parse_args()
    r = run(a.case, a.seeds, a.noise)
    n = r["converged"]
    print(f"{r['case']}: {r['dofs']} DOFs, {n} of {r['seeds']} fits converged ({r['mean_solves']:.1f} whole-test "
          f"solves each), design {r['design_s']:.2f} s, fits {r['fits_s']:.1f} s; predicted verdict {r['verdict']}, "
          f"correlation {r['correlation']:+.4f}; sampling error of a standard deviation ≈ "
          f"{100 / np.sqrt(2 * (n - 1)):.0f} %")
    print("| constant | true | mean of fits | predicted SE | scatter of fits | scatter / predicted |")
    print("|---|---|---|---|---|---|")
    for name, se, sd, mean in r["rows"]:
        print(f"| {name} | {TRUE[name]:g} | {mean:.5g} | {se:.4g} | {sd:.4g} | {sd / se:.3f} |")


if __name__ == "__main__":
    main()
