"""Raw force–displacement records (a testing machine's export) → a cleaned stretch–stress curve.

    [[data]]
    file = "specimen-B.csv"
    kind = "uniaxial"                 # uniaxial | planar (a strip: the same geometry)
    columns = { displacement = "ext_mm", force = "load_N" }   # optional: time = "t_s"
    zero = "toe"                      # none | first | toe
    trim = [1.0, 3.0]                 # stretch range kept
    resample = 50                     # points evenly spaced in stretch
    smooth = 7                        # Savitzky–Golay window (odd, ≥ 5), or "none"
    [data.geometry]
    gauge_length = 25.0               # in length_units
    width = 6.0
    thickness = 2.0                   # or area = 12.0 (in length_units²)
    force_units = "N"                 # N | kN | lbf | kgf
    length_units = "mm"               # mm | m | in

Units are converted by pint (force → N, length → mm), so stress = F / A0 is in N/mm² = MPa and
the stretch λ = 1 + u / L0. The clean-up steps run in this order, each recorded:

- zero = "first": the first row's displacement and force are subtracted (the offset).
- zero = "toe" (ASTM D638's toe compensation): the first row's force is subtracted (the load
  cell's offset), then the steepest straight part of the curve is found — the least-squares line
  F = s (u − u0) over the ``toe_window`` (default 5) consecutive points of largest slope s among
  the points below half the peak force — and its intercept u0 with F = 0 becomes the zero of
  displacement: u → u − u0, the rows with u < u0 (the toe) are dropped and the point (0, 0)
  is put first. Exact when the steepest part is straight (a linear start of the curve).
- trim = [lo, hi]: only points with lo ≤ λ ≤ hi are kept.
- resample = n: n points evenly spaced in λ over the kept range, linear interpolation (error
  ≤ h²/8 max|P''| with h the spacing of the data).
- smooth = w: a Savitzky–Golay filter (window w, polynomial order 3; scipy.signal.savgol_filter)
  of the stress, the ends with the polynomial fitted to the edge window ("interp" mode).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table
from vlab.identify.datasets import Dataset, check_monotonic, read_columns

__all__ = ["is_raw", "raw_dataset", "clean", "FORCE_UNITS", "LENGTH_UNITS"]

FORCE_UNITS = ("N", "kN", "lbf", "kgf")
LENGTH_UNITS = ("mm", "m", "in")
KINDS = ("uniaxial", "planar")
KEYS = ("file", "kind", "columns", "role", "weight", "name", "zero", "trim", "resample", "smooth",
        "toe_window", "geometry")


def is_raw(raw) -> bool:
    """A [[data]] table giving a force and displacement column (a machine export), unless its kind
    reads a force column of its own (FE in the loop, or a closed-form kind of vlab.identify.kinds)."""
    from vlab.identify.kinds import FIT_KINDS

    cols = raw.get("columns") if isinstance(raw, dict) else None
    own = raw.get("kind") == "specimen" or raw.get("kind") in FIT_KINDS
    return isinstance(cols, dict) and ("force" in cols or "displacement" in cols) and not own


def _factor(unit: str, to: str) -> float:
    """The factor of ``unit`` in ``to`` through pint (kgf: standard gravity 9.80665 m/s²)."""
    import pint

    ureg = _registry(pint)
    return float(ureg.Quantity(1.0, unit).to(to).magnitude)


_UREG = []


def _registry(pint):
    if not _UREG:
        _UREG.append(pint.UnitRegistry())
    return _UREG[0]


def _geometry(t: Table, file: str) -> dict:
    if "geometry" not in t.raw:
        raise SceneError(f"{t.field('geometry')}: the raw force–displacement record {file!r} needs its specimen's "
                         "geometry to become stress and stretch: [data.geometry] gauge_length and width + "
                         "thickness (or area), with force_units and length_units")
    g = Table(t.field("geometry"), t.raw["geometry"], ("gauge_length", "width", "thickness", "area",
                                                        "force_units", "length_units"))
    length = g.number("gauge_length", gt=0, note=" (length_units: the extensometer's or the grips' distance)")
    if "area" in g.raw and ("width" in g.raw or "thickness" in g.raw):
        raise SceneError(f"{g.field('area')}: give area or width and thickness, not both")
    if "area" in g.raw:
        area = g.number("area", gt=0, note=" (length_units²)")
    else:
        if "width" not in g.raw or "thickness" not in g.raw:
            raise SceneError(f"{g.field('width')} and {g.field('thickness')} (or {g.field('area')}) are required: "
                             "the cross-section the force is divided by")
        area = g.number("width", gt=0) * g.number("thickness", gt=0)
    fu = g.choice("force_units", FORCE_UNITS, "N")
    lu = g.choice("length_units", LENGTH_UNITS, "mm")
    mm = _factor(lu, "mm")
    return {"gauge_length_mm": length * mm, "area_mm2": area * mm * mm, "force_units": fu, "length_units": lu,
            "force_factor_N": _factor({"lbf": "lbf", "kgf": "kgf"}.get(fu, fu), "N"), "length_factor_mm": mm}


def _options(t: Table) -> dict:
    zero = t.choice("zero", ("none", "first", "toe"), "none")
    trim = t.get("trim", None)
    if trim is not None:
        if not isinstance(trim, list) or len(trim) != 2:
            raise SceneError(f"{t.field('trim')} must be [lo, hi], the stretch range kept, got {fields.show(trim)}")
        lo = fields.number(t.field("trim") + "[0]", trim[0], gt=0)
        hi = fields.number(t.field("trim") + "[1]", trim[1], gt=lo)
        trim = (lo, hi)
    resample = t.integer("resample", 3, 100000, None) if "resample" in t.raw else None
    smooth = t.get("smooth", "none")
    if smooth != "none":
        smooth = fields.integer(t.field("smooth"), smooth, 5, 10001)
        if smooth % 2 == 0:
            raise SceneError(f"{t.field('smooth')} must be an odd window (Savitzky–Golay, order 3), got {smooth}")
    return {"zero": zero, "trim": trim, "resample": resample, "smooth": smooth,
            "toe_window": t.integer("toe_window", 2, 1000, 5)}


def raw_dataset(raw, i: int, base: Path) -> Dataset:
    """The cleaned Dataset of a raw [[data]] table; ``extra["cleanup"]`` records every step."""
    t = Table(f"data[{i}]", raw, KEYS)
    file = t.get("file")
    if not isinstance(file, str) or not file:
        raise SceneError(f"{t.field('file')} must be a CSV file name (string), got {fields.show(file)}")
    kind = t.choice("kind", KINDS)
    ct = Table(t.field("columns"), t.raw["columns"], ("displacement", "force", "time"))
    wanted = {k: ct.raw.get(k, k) for k in ("displacement", "force")} | (
        {"time": ct.raw["time"]} if "time" in ct.raw else {})
    for k, v in wanted.items():
        if not isinstance(v, str) or not v:
            raise SceneError(f"{ct.field(k)} must be a column name (string), got {fields.show(v)}")
    geo = _geometry(t, file)
    opts = _options(t)
    role = t.choice("role", ("fit", "validate"), "fit")
    weight = t.number("weight", 1.0, gt=0)
    name = str(t.get("name", Path(file).stem))
    path = (base / file).resolve()
    cols = read_columns(path, wanted)
    lines = cols["_line"]
    if "time" in cols:
        check_increasing(path, wanted["time"], cols["time"], lines)
    check_monotonic(path, wanted["displacement"], cols["displacement"], lines)
    u = cols["displacement"] * geo["length_factor_mm"]
    F = cols["force"] * geo["force_factor_N"]
    lam, P, record = clean(u, F, geo["gauge_length_mm"], geo["area_mm2"], opts, path.name, wanted, lines)
    record["geometry"] = geo
    record["raw"] = {"stretch": 1.0 + (u - u[0]) / geo["gauge_length_mm"], "stress": F / geo["area_mm2"]}
    return Dataset(name, str(path), kind, role, weight, "nominal", lam, None, P, extra={"cleanup": record})


def check_increasing(path: Path, column: str, v: np.ndarray, lines) -> None:
    """A time column must increase strictly, row after row."""
    bad = np.nonzero(np.diff(v) <= 0)[0]
    if len(bad):
        j = int(bad[0]) + 1
        raise SceneError(f"{path.name} row {int(lines[j])} column {column!r}: time {v[j]:g} after {v[j - 1]:g} — "
                         "time must increase strictly")


def _toe(u, F, window: int):
    """(u0, slope, first index of the window): the steepest least-squares line over ``window``
    consecutive points below half the peak force, and its zero-force intercept."""
    below = np.nonzero(F <= 0.5 * np.max(F))[0]
    last = int(below[-1]) if len(below) else len(F) - 1
    best = None
    for k in range(0, max(1, last - window + 2)):
        uu, ff = u[k:k + window], F[k:k + window]
        if len(uu) < 2:
            break
        s = np.polyfit(uu, ff, 1)[0]
        if best is None or s > best[0]:
            best = (s, k, float(np.mean(uu)), float(np.mean(ff)))
    s, k, ub, fb = best
    if s <= 0:
        return None
    return ub - fb / s, float(s), k


def clean(u, F, L0: float, A0: float, opts: dict, fname: str, wanted: dict, lines):
    """(λ, P MPa, record) of displacements u (mm) and forces F (N) after the clean-up in opts:
    zero, then λ = 1 + u/L0 and P = F/A0, then trim, resample and smooth (module docstring)."""
    steps = []
    u, F = _zeroed(np.array(u, float), np.array(F, float), opts, fname, wanted, lines, steps)
    lam, P = 1.0 + u / L0, F / A0
    if opts["trim"] is not None:
        lam, P = _trimmed(lam, P, opts["trim"], fname, steps)
    if opts["resample"] is not None:
        lam, P = _resampled(lam, P, opts["resample"], steps)
    if opts["smooth"] != "none":
        P = _smoothed(P, opts["smooth"], fname, steps)
    if np.any(lam <= 0):
        raise SceneError(f"{fname}: a displacement below -gauge_length gives a stretch ≤ 0")
    return lam, P, {"steps": steps, "points": int(len(lam))}


def _zeroed(u, F, opts: dict, fname: str, wanted: dict, lines, steps: list):
    """(u, F) after opts["zero"]: "first" subtracts the first row, "toe" compensates the toe,
    "none" only counts u from the first reading; the step is appended to ``steps``."""
    if opts["zero"] == "first":
        steps.append({"step": "zero", "method": "first", "displacement_offset_mm": float(u[0]),
                      "force_offset_N": float(F[0])})
        return u - u[0], F - F[0]
    if opts["zero"] == "toe":
        return _toe_zeroed(u, F, opts["toe_window"], fname, wanted, lines, steps)
    return u - u[0], F  # the stretch counts from the first reading (no force correction)


def _toe_zeroed(u, F, window: int, fname: str, wanted: dict, lines, steps: list):
    """Toe compensation: F − F₀, then u − u0 with u0 the zero-force intercept of the steepest
    line (_toe), the toe (u ≤ u0) dropped and (0, 0) put first."""
    f0 = float(F[0])
    F = F - f0
    found = _toe(u, F, window)
    if found is None:
        raise SceneError(f"{fname} column {wanted['force']!r}: zero = \"toe\" found no rising straight part "
                         "(the force never increases with displacement)")
    u0, s, k = found
    keep = u > u0
    steps.append({"step": "zero", "method": "toe", "force_offset_N": f0, "toe_end_mm": float(u0),
                  "toe_extent_mm": float(u0 - u[0]), "slope_N_per_mm": s,
                  "line_rows": [int(lines[k]), int(lines[min(k + window, len(lines)) - 1])],
                  "points_removed": int(np.sum(~keep))})
    return np.r_[0.0, u[keep] - u0], np.r_[0.0, F[keep]]


def _trimmed(lam, P, trim, fname: str, steps: list):
    """The points with lo ≤ λ ≤ hi (at least 3 must be left)."""
    lo, hi = trim
    keep = (lam >= lo) & (lam <= hi)
    steps.append({"step": "trim", "range": [lo, hi], "points_removed": int(np.sum(~keep)),
                  "points_kept": int(np.sum(keep))})
    if np.sum(keep) < 3:
        raise SceneError(f"{fname}: trim = [{lo:g}, {hi:g}] keeps {int(np.sum(keep))} points (stretch of the record "
                         f"{float(np.min(lam)):g} … {float(np.max(lam)):g}); at least 3 are needed")
    return lam[keep], P[keep]


def _resampled(lam, P, n: int, steps: list):
    """n points evenly spaced in λ over the kept range, P linearly interpolated."""
    grid = np.linspace(lam[0], lam[-1], n)
    steps.append({"step": "resample", "points_before": int(len(lam)), "points": n,
                  "spacing": float(grid[1] - grid[0])})
    return grid, np.interp(grid, lam, P)


def _smoothed(P, w: int, fname: str, steps: list):
    """P through a Savitzky–Golay filter (window w, order 3, "interp" ends)."""
    from scipy.signal import savgol_filter

    if w > len(P):
        raise SceneError(f"{fname}: smooth = {w} is longer than the {len(P)} points left after the clean-up")
    Ps = savgol_filter(P, w, 3, mode="interp")
    steps.append({"step": "smooth", "method": "savitzky-golay", "window": w, "order": 3,
                  "largest_change_MPa": float(np.max(np.abs(Ps - P)))})
    return Ps
