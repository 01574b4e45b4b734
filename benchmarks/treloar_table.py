"""The README's Treloar table: every model fitted on one mode (or all three), rms relative error
on each mode (the held-out modes predicted).

    python -m benchmarks.treloar_table

Incompressible forms, relative residuals, 20 starts (seed 0), specimens/treloar1944/*.csv.
"""

from __future__ import annotations

from pathlib import Path

from vlab.identify.fitfile import parse_fit
from vlab.identify.fitting import fit_homogeneous

ROOT = Path(__file__).resolve().parents[1] / "specimens" / "treloar1944"
MODES = {"uniaxial": "uniaxial", "equibiaxial": "equibiaxial", "pure_shear": "planar"}
MODELS = ("neo-hookean", "mooney-rivlin", "yeoh", "gent", "arruda-boyce", "ogden-2", "ogden-3")


def fit(model: str, fitted: tuple[str, ...]) -> dict:
    data = {"name": "treloar", "model": {"name": model}, "options": {"starts": 20, "seed": 0},
            "data": [{"file": f"{f}.csv", "kind": k, "role": "fit" if f in fitted else "validate",
                      "columns": {"stretch": "stretch", "stress": "nominal_stress_MPa"}} for f, k in MODES.items()]}
    return fit_homogeneous(parse_fit(data, ROOT)).data


def main() -> None:
    print("| model | fitted on | uniaxial | equibiaxial | planar | stable over fitted ranges |")
    print("| --- | --- | --- | --- | --- | --- |")
    for model in MODELS:
        for fitted in (("uniaxial",), ("equibiaxial",), ("pure_shear",), tuple(MODES)):
            d = fit(model, fitted)
            cells = []
            for x in d["datasets"]:
                text = f"{100 * x['rms_relative']:.3g} %"
                cells.append(text if x["role"] == "fit" else f"*{text}*")
            label = "all three" if len(fitted) == 3 else MODES[fitted[0]]
            print(f"| {model} | {label} | {' | '.join(cells)} | "
                  f"{'yes' if d['stability']['stable_over_all_fitted_ranges'] else 'no'} |")


if __name__ == "__main__":
    main()
