"""Record kind "dma": a dynamic mechanical analysis sweep, storage and loss modulus over frequency.

    [[data]]
    file = "dma.csv"
    kind = "dma"
    columns = { frequency = "f", storage = "E1", loss = "E2" }   # frequency in Hz
    modulus = "tensile"        # tensile (E', E'') | shear (G', G'')
    units = "MPa"              # the moduli's unit (datasets.STRESS_UNITS)

The linear-viscoelastic moduli of the Prony series at small strain (prony.dynamic_moduli), with
the same β_i, τ_i as the time-domain records of the fit. Frequencies > 0, storage > 0, loss ≥ 0
(a negative loss would be a material that gives energy back). Dataset: a = frequency (Hz),
y = [storage…, loss…] (MPa); extra["modulus"].
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table
from vlab.identify.datasets import STRESS_UNITS, Dataset, read_columns
from vlab.identify.records.prony import dynamic_moduli, without_mullins

KIND = "dma"
NEEDS_PRONY = True
XLABEL = "frequency f (Hz)"


def parse(raw, i: int, base: Path) -> Dataset:
    t = Table(f"data[{i}]", raw, ("file", "kind", "columns", "modulus", "units", "role", "weight", "name"))
    file = t.get("file")
    if not isinstance(file, str) or not file:
        raise SceneError(f"{t.field('file')} must be a CSV file name (string), got {fields.show(file)}")
    modulus = t.choice("modulus", ("tensile", "shear"), "tensile")
    unit = t.choice("units", tuple(STRESS_UNITS), "MPa")
    ct = Table(t.field("columns"), t.get("columns", {}), ("frequency", "storage", "loss"))
    wanted = {k: ct.raw.get(k, k) for k in ("frequency", "storage", "loss")}
    for k, v in wanted.items():
        if not isinstance(v, str) or not v:
            raise SceneError(f"{ct.field(k)} must be a column name (string), got {fields.show(v)}")
    path = (base / file).resolve()
    cols = read_columns(path, wanted)
    lines = cols["_line"]
    checks = (("frequency", cols["frequency"] > 0, "frequency must be > 0 (Hz)"),
              ("storage", cols["storage"] > 0, "the storage modulus must be > 0"),
              ("loss", cols["loss"] >= 0, "the loss modulus must be ≥ 0 (a negative one would give energy back)"))
    for key, ok, what in checks:
        if not np.all(ok):
            j = int(np.argmin(ok))
            raise SceneError(f"{path.name} row {int(lines[j])} column {wanted[key]!r}: {what}, got {cols[key][j]:g}")
    y = np.r_[cols["storage"], cols["loss"]] * STRESS_UNITS[unit]
    return Dataset(str(t.get("name", Path(file).stem)), str(path), KIND, t.choice("role", ("fit", "validate"), "fit"),
                   t.number("weight", 1.0, gt=0), "nominal", cols["frequency"], None, y,
                   extra={"modulus": modulus})


def predict(model, effects, X, d):
    prony = effects.get("viscoelastic")  # a virgin specimen at small strain is on the primary path: η = 1
    s, l = dynamic_moduli(model, prony, without_mullins(X, effects), d.a, d.extra["modulus"])
    return np.concatenate([s, l], axis=-1)


def scale(d) -> float:
    """μ estimate (MPa): the storage modulus at the lowest frequency (/3 for tensile)."""
    j = int(np.argmin(d.a))
    return float(d.y[j] / (3.0 if d.extra["modulus"] == "tensile" else 1.0))


def time_range(d) -> tuple[float, float]:
    """(shortest, longest) time scale the sweep probes: 1/(2π f_max), 1/(2π f_min) s."""
    return float(1.0 / (2 * np.pi * np.max(d.a))), float(1.0 / (2 * np.pi * np.min(d.a)))


def curve(model, effects, x, d):
    return d.a, np.real(predict(model, effects, np.asarray(x, float)[None, :], d)[0])
