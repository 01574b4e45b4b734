"""Benchmark: FE-in-the-loop identification on a dumb-bell curve vlab produced itself.

    python -m benchmarks.fit_fe_dogbone [--model neo-hookean|mooney-rivlin] [--noise 0.01] [--seed 0] [--start 1.5]

The ISO 37 type 2 dumb-bell (hexahedra, order 1, mesh.size 2) in Neo-Hookean rubber (mu = 0.5 MPa,
K = 5 MPa; mu and K fitted) or Mooney–Rivlin rubber (C10 = 0.2, C01 = 0.05 MPa, K = 4 MPa held;
C10 and C01 fitted, the issue's target; needs the FE model library of #18), pulled to grip stretch
1.6 in 8 steps; the readings (extensometer strain, load-cell force) get 1 % relative Gaussian noise
on the force; the fit starts at ``start`` × the true constants and may use 15 whole-test solves. Prints the solves, the fitted constants
with their standard errors, the error in standard errors, and the homogeneous (closed-form
uniaxial) fit of the same readings.
"""

from __future__ import annotations

import argparse
import os
import json
import tempfile
import time
from pathlib import Path

import numpy as np

SCENE = '''name = "bench-dumbbell"
[specimen]
shape = "dogbone"
standard = "ISO 37 2"
[mesh]
size = 2.0
order = 1
cell = "hex"
[material]
{material}
[test]
kind = "uniaxial"
stretch = 1.6
steps = 8
'''
CASES = {"neo-hookean": ({"mu": 0.5, "K": 5.0}, {}, ("mu", "K")),
         "mooney-rivlin": ({"C10": 0.2, "C01": 0.05}, {"K": 4.0}, ("C10", "C01"))}


def material(model: str, values: dict) -> str:
    return f'model = "{model}"\n' + "".join(f"{k} = {v!r}\n" for k, v in values.items())


def _factor_reuse(fe, values, simulate) -> None:
    """A/B, interleaved: sensitivities with the monitor's factor against K assembled and
    factorized again at each level (the previous way)."""
    rows = {False: [], True: []}
    for refactorize in (False, True, False, True):
        t = time.perf_counter()
        sim = simulate(fe, values, refactorize=refactorize)
        rows[refactorize].append((time.perf_counter() - t, sim.counts))
    for refactorize, label in ((False, "monitor's factor"), (True, "own factorization")):
        times = [r[0] for r in rows[refactorize]]
        counts = rows[refactorize][0][1]
        print(f"  one whole test, sensitivities with the {label}: {counts['total_factorizations']} factorizations "
              f"({counts['sensitivity_factorizations']} by the sensitivities), {counts['sensitivity_solves']} "
              f"back-substitutions, wall {min(times):.2f} s (min of 2)")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--noise", type=float, default=0.01)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--start", type=float, default=1.5)
    ap.add_argument("--model", choices=tuple(CASES), default="neo-hookean")
    args = ap.parse_args()
    TRUE, held, names = CASES[args.model]
    text = SCENE.format(material=material(args.model, TRUE | held))
    from vlab.identify.fitfile import load_fit
    from vlab.identify.fe_loop import fit_specimen
    from vlab.identify.fe_sensitivity import simulate
    import tomllib

    tmp = Path(tempfile.mkdtemp(prefix="vlab-fe-bench-"))
    (tmp / "dumbbell.toml").write_text(text)
    fe = {"scene_path": str(tmp / "dumbbell.toml"), "scene_raw": tomllib.loads(text),
          "parameters": names[:1], "model": args.model, "volumetric": None}
    t = time.perf_counter()
    s = simulate(fe, TRUE | held)
    one = time.perf_counter() - t
    _factor_reuse(fe, TRUE | held, simulate)
    rng = np.random.default_rng(args.seed)
    force = s.force[:, 0] * (1 + args.noise * rng.standard_normal(len(s.force[:, 0])))
    (tmp / "readings.csv").write_text("strain,force\n" + "".join(f"{e:.17g},{f:.17g}\n" for e, f in zip(s.strain[:, 0], force)))
    start = {k: args.start * v for k, v in TRUE.items()}
    (tmp / "fit.toml").write_text(f'''name = "bench-fe"
[model]
name = "{args.model}"
[[data]]
file = "readings.csv"
kind = "specimen"
columns = {{ strain = "strain", force = "force" }}
[fe]
scene = "dumbbell.toml"
parameters = {list(names)!r}
start = {{ {", ".join(f"{n} = {start[n]!r}" for n in names)} }}
max_solves = 15
cache = false
''')
    t, c = time.perf_counter(), time.process_time()
    out = fit_specimen(load_fit(tmp / "fit.toml"))
    wall, cpu = time.perf_counter() - t, time.process_time() - c
    d = out.data
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())} on {os.cpu_count()} cores")
    print(f"dumb-bell: {s.dofs} DOFs, {len(s.strain[:, 0])} recorded levels, one solve + sensitivities "
          f"{one:.1f} s; fit wall {wall:.1f} s, CPU {cpu:.1f} s, {d['fe']['solves']} whole-test solves, "
          f"converged {d['converged']}; counts over the fit {d['fe']['counts']}")
    for n in names:
        v, se = d["parameters"][n], d["uncertainty"][n]["standard_error"]
        print(f"  {n}: true {TRUE[n]:g}, start {start[n]:g}, fitted {v:.6g} ± {se:.3g}  "
              f"(error {(v - TRUE[n]) / se:+.2f} standard errors)")
    hom = d["fe"]["homogeneous_fit"]
    print(f"  homogeneous fit of the same readings: {json.dumps(hom['parameters'])}; "
          f"relative difference from the FE fit {json.dumps({k: round(v, 5) for k, v in hom['relative_difference'].items()})}")
    print(f"  objective by solve: {[round(x['objective'], 6) for x in d['fe']['trail']]}")


if __name__ == "__main__":
    main()
