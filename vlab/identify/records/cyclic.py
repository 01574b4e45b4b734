"""Record kind "cyclic": loading–unloading cycles (rising amplitudes) of one homogeneous test.

    [[data]]
    file = "cycles.csv"
    kind = "cyclic"
    columns = { stretch = "lambda", stress = "P" }   # or strain; optional time = "t"
    branch = "all"              # all | loading | unloading: the points the residual takes
    test = "uniaxial"           # uniaxial | equibiaxial | planar
    units = "MPa"

The rows are the history in the order it happened (the first row the first point after rest at
λ = 1); the model runs over all of them, the residual takes the chosen branch (loading: the
points where the stretch rose from the row before, the first row included; unloading: where it
fell). With [model] mullins the stress is the Ogden–Roxburgh softened ground law
(softening.py); with [model] viscoelastic the Prony history (needs the time column); with both,
the softened ground law plus the Maxwell branches,

    P_1 = η(ψ0, W_max) P0 + (λ1² ΣQ_1 − λ_f² ΣQ_f)/λ1        (MPa; prony.branch_stress),

the softening acting on the long-term (equilibrium) response only and the branches, Neo-Hookean
of μ0 as in vlab's viscoelastic effect, not softened (as Abaqus applies its Mullins effect to the
long-term modulus of a viscoelastic material); with neither, the ground law, and a record that
returns below its earlier maximum gets a warning with the misfit. Dataset: a = stretch at the residual's points, y = nominal stress there (MPa);
extra = {"test", "stretch" (every row), "time" (or None), "mask"}.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table
from vlab.identify.datasets import STRESS_UNITS, Dataset, read_columns
from vlab.identify.records.prony import branch_stress, principal, without_mullins
from vlab.identify.records.raw import check_increasing

KIND = "cyclic"
NEEDS_PRONY = False
XLABEL = "stretch λ"
TESTS = ("uniaxial", "equibiaxial", "planar")


def parse(raw, i: int, base: Path) -> Dataset:
    t = Table(f"data[{i}]", raw, ("file", "kind", "columns", "branch", "test", "units", "role", "weight", "name"))
    file = t.get("file")
    if not isinstance(file, str) or not file:
        raise SceneError(f"{t.field('file')} must be a CSV file name (string), got {fields.show(file)}")
    branch = t.choice("branch", ("all", "loading", "unloading"), "all")
    test = t.choice("test", TESTS, "uniaxial")
    unit = t.choice("units", tuple(STRESS_UNITS), "MPa")
    ct = Table(t.field("columns"), t.get("columns", {}), ("time", "stretch", "strain", "stress"))
    if "stretch" in ct.raw and "strain" in ct.raw:
        raise SceneError(f"{ct.field('stretch')}: give stretch or strain, not both")
    control = "strain" if "strain" in ct.raw else "stretch"
    wanted = {control: ct.raw.get(control, control), "stress": ct.raw.get("stress", "stress")}
    if "time" in ct.raw:
        wanted["time"] = ct.raw["time"]
    for k, v in wanted.items():
        if not isinstance(v, str) or not v:
            raise SceneError(f"{ct.field(k)} must be a column name (string), got {fields.show(v)}")
    path = (base / file).resolve()
    cols = read_columns(path, wanted)
    lines = cols["_line"]
    lam = cols[control] + (1.0 if control == "strain" else 0.0)
    if np.any(lam <= 0):
        j = int(np.argmax(lam <= 0))
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted[control]!r}: stretch must be > 0")
    time = cols.get("time")
    if time is not None:
        check_increasing(path, wanted["time"], time, lines)
    step = np.diff(np.r_[1.0, lam])
    mask = {"all": np.ones(len(lam), bool), "loading": step >= 0, "unloading": step < 0}[branch]
    if mask.sum() < 2:
        raise SceneError(f"{path.name}: branch = {branch!r} keeps {int(mask.sum())} points; the record's stretch "
                         f"runs {lam.min():g} … {lam.max():g}")
    return Dataset(str(t.get("name", Path(file).stem)), str(path), KIND, t.choice("role", ("fit", "validate"), "fit"),
                   t.number("weight", 1.0, gt=0), "nominal", lam[mask], None, cols["stress"][mask] * STRESS_UNITS[unit],
                   extra={"test": test, "stretch": lam, "time": time, "mask": mask, "branch": branch})


def stress_along(model, effects, X, test, lam, time=None):
    """Nominal stress (m, n) over a whole cyclic history."""
    from vlab.identify.records.softening import softened_stress

    prony, mullins = effects.get("viscoelastic"), effects.get("mullins")
    c, _ = model.split(np.asarray(X)[:, None, :])
    l1, l2, l3, f = principal(test, lam)
    w = model.law.w(c, l1[None, :], l2[None, :], l3[None, :])
    P = (w[0] - w[f]) / l1[None, :] + 0.0 * c[0]
    if mullins is not None:
        P = softened_stress(model.law, mullins, np.asarray(X), c, P, l1, l2, l3)
    if prony is not None:
        P = P + branch_stress(model, prony, without_mullins(X, effects), test, time, lam)
    return P


def predict(model, effects, X, d):
    return stress_along(model, effects, X, d.extra["test"], d.extra["stretch"], d.extra["time"])[:, d.extra["mask"]]


def scale(d) -> float:
    """μ estimate (MPa): the stress at the largest stretch (on the primary curve) against NH μ = 1."""
    lam = d.extra["stretch"]
    j = int(np.argmax(lam))
    l1, l2, l3, f = principal(d.extra["test"], lam[j:j + 1])
    base = float(((l1 ** 2 - (l1, l2, l3)[f] ** 2) / l1)[0])
    k = np.nonzero(np.nonzero(d.extra["mask"])[0] == j)[0]
    return float(d.y[k[0]] / base) if len(k) and base > 1e-9 else 1.0


def time_range(d):
    if d.extra["time"] is None:
        return None
    dt = np.diff(np.r_[0.0, d.extra["time"]])
    return float(np.min(dt[dt > 0])), float(d.extra["time"][-1])


def below_maximum(d) -> bool:
    """Whether the record returns below its earlier largest stretch (unloading or reloading)."""
    lam = d.extra["stretch"]
    return bool(np.any(lam < np.maximum.accumulate(lam) - 1e-12))


def curve(model, effects, x, d):
    return d.a, np.real(predict(model, effects, np.asarray(x, float)[None, :], d)[0])
