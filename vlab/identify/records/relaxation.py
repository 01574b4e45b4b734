"""Record kind "relaxation": a whole ramp-and-hold (or any timed) record of one homogeneous test.

    [[data]]
    file = "relaxation.csv"
    kind = "relaxation"
    columns = { time = "t", stretch = "lambda", stress = "P" }   # or strain = "..." (λ = 1 + ε)
    test = "uniaxial"           # uniaxial | equibiaxial | planar: the homogeneous state
    units = "MPa"               # the stress column's unit (datasets.STRESS_UNITS)

Time (s) must increase strictly; the history starts at rest (t = 0, λ = 1), as `vlab run` starts,
so a first row at t = 0 must have λ = 1. Predicted with cyclic.stress_along (the ground law plus
prony.branch_stress, softened by [model] mullins when given — inert on a monotonic ramp and hold,
where ψ0 is its own maximum): the model is run over the record's own times, step for step as
vlab's viscoelastic effect integrates them.
Dataset: a = time (s), b = stretch, y = nominal stress (MPa); extra["test"] the kind.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table
from vlab.identify.datasets import STRESS_UNITS, Dataset, read_columns
from vlab.identify.records.raw import check_increasing

KIND = "relaxation"
NEEDS_PRONY = False  # fitted without one, it is the ground law's curve and a warning gives the misfit
XLABEL = "time t (s)"
TESTS = ("uniaxial", "equibiaxial", "planar")


def parse(raw, i: int, base: Path) -> Dataset:
    t = Table(f"data[{i}]", raw, ("file", "kind", "columns", "test", "units", "role", "weight", "name"))
    file = t.get("file")
    if not isinstance(file, str) or not file:
        raise SceneError(f"{t.field('file')} must be a CSV file name (string), got {fields.show(file)}")
    test = t.choice("test", TESTS, "uniaxial")
    unit = t.choice("units", tuple(STRESS_UNITS), "MPa")
    ct = Table(t.field("columns"), t.get("columns", {}), ("time", "stretch", "strain", "stress"))
    if "stretch" in ct.raw and "strain" in ct.raw:
        raise SceneError(f"{ct.field('stretch')}: give stretch or strain, not both")
    control = "strain" if "strain" in ct.raw else "stretch"
    wanted = {"time": ct.raw.get("time", "time"), control: ct.raw.get(control, control),
              "stress": ct.raw.get("stress", "stress")}
    for k, v in wanted.items():
        if not isinstance(v, str) or not v:
            raise SceneError(f"{ct.field(k)} must be a column name (string), got {fields.show(v)}")
    path = (base / file).resolve()
    cols = read_columns(path, wanted)
    lines = cols["_line"]
    time = cols["time"]
    lam = cols[control] + (1.0 if control == "strain" else 0.0)
    check_increasing(path, wanted["time"], time, lines)
    if time[0] < 0:
        raise SceneError(f"{path.name} row {int(lines[0])} column {wanted['time']!r}: time {time[0]:g} < 0; the "
                         "history starts at rest at t = 0")
    if time[0] == 0 and abs(lam[0] - 1.0) > 1e-12:
        raise SceneError(f"{path.name} row {int(lines[0])} column {wanted[control]!r}: stretch {lam[0]:g} at t = 0; "
                         "the history starts at rest (stretch 1 at t = 0)")
    if np.any(lam <= 0):
        j = int(np.argmax(lam <= 0))
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted[control]!r}: stretch must be > 0")
    return Dataset(str(t.get("name", Path(file).stem)), str(path), KIND, t.choice("role", ("fit", "validate"), "fit"),
                   t.number("weight", 1.0, gt=0), "nominal", time, lam, cols["stress"] * STRESS_UNITS[unit],
                   extra={"test": test})


def predict(model, effects, X, d):
    from vlab.identify.records.cyclic import stress_along  # with [model] mullins too: the joint model

    return stress_along(model, effects, X, d.extra["test"], d.b, d.a)


def scale(d) -> float:
    """μ estimate (MPa): the last point against an incompressible Neo-Hookean of μ = 1."""
    from vlab.identify.records.prony import principal

    l1, l2, l3, f = principal(d.extra["test"], d.b[-1:])
    base = float(((l1 ** 2 - (l1, l2, l3)[f] ** 2) / l1)[0])
    return float(d.y[-1] / base) if abs(base) > 1e-9 else 1.0


def time_range(d) -> tuple[float, float]:
    """(smallest positive step, span) of the record's times, s: the τ bounds follow them."""
    dt = np.diff(np.r_[0.0, d.a])
    return float(np.min(dt[dt > 0])), float(d.a[-1])


def curve(model, effects, x, d):
    """(x values, prediction at the data) for the figure: the record is its own grid."""
    return d.a, np.real(predict(model, effects, np.asarray(x, float)[None, :], d)[0])
