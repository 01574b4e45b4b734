"""Measured curves from CSV files, validated with the file, row (file line) and column in errors.

Stresses are converted to MPa (MPa, N/mm2: 1; kPa: 1e-3; Pa: 1e-6; kgf/cm2: 0.0980665) and
strains to stretches (λ = 1 + ε). Forces (kind "specimen") are in N (N: 1, kN: 1e3).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vlab.fields import SceneError, suggest
from vlab.scene.file import MAX_DATA_BYTES, read_text_file

__all__ = ["Dataset", "STRESS_UNITS", "FORCE_UNITS", "read_columns", "COLUMN_KEYS", "check_plausible"]

STRESS_UNITS = {"MPa": 1.0, "N/mm2": 1.0, "kPa": 1e-3, "Pa": 1e-6, "kgf/cm2": 0.0980665}
FORCE_UNITS = {"N": 1.0, "kN": 1e3}

# column keys per kind: (required, optional); "stretch" may be given as "strain" instead
COLUMN_KEYS = {
    "uniaxial": (("stretch", "stress"), ()),
    "equibiaxial": (("stretch", "stress"), ()),
    "planar": (("stretch", "stress"), ()),
    "biaxial": (("stretch", "stretch2", "stress", "stress2"), ()),
    "simple-shear": (("shear", "stress"), ()),
    "specimen": (("strain", "force"), ("strain2", "force2")),
    "volumetric": (("volume_ratio", "stress"), ()),
}


@dataclass(frozen=True, eq=False)
class Dataset:
    """One data set: ``a`` controlled stretch (or shear γ, or specimen strain), ``b`` biaxial λ2,
    ``y`` measured stress in MPa (biaxial: stress along 1 then along 2; specimen: force in N)."""

    name: str
    file: str
    kind: str
    role: str
    weight: float
    measure: str
    a: np.ndarray
    b: np.ndarray | None
    y: np.ndarray
    extra: dict | None = None
    specimen: str | None = None  # fit file's specimen = "<id>" (vlab.identify.specimens)

    @property
    def points(self) -> int:
        return len(self.a)


def _cell(path: Path, line: int, column: str, text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise SceneError(f"{path.name} row {line} column {column!r}: {text!r} is not a number") from None
    if not math.isfinite(v):
        raise SceneError(f"{path.name} row {line} column {column!r}: {text!r} is not a finite number "
                         "(NaN and infinities are not data)")
    return v


def _missing_column(path: Path, key: str, name: str, header: list[str], others_found: bool) -> str:
    """The error of a column the header lacks. The header is echoed only when it names another
    wanted column (a data file of vlab's): a file whose first line names none of them may be any
    file (a system file given by mistake), and an error never prints its content."""
    if others_found:
        return (f"{path.name}: missing column {name!r} (columns.{key}); the header has "
                f"{', '.join(repr(h) for h in header)}{suggest(name, header)}")
    return (f"{path.name}: missing column {name!r} (columns.{key}): its first line names none of the "
            f"columns the data set asks for; a data file is a CSV whose first row names its columns "
            f"(e.g. {name}), then one row of numbers per point{suggest(name, header)}")


def _csv_rows(path: Path) -> list[list[str]]:
    """The rows of a CSV file read as every vlab input is (bounded, UTF-8, a BOM dropped)."""
    text = read_text_file(path, "data file", MAX_DATA_BYTES, encoding="utf-8-sig")
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        return list(reader)
    except csv.Error as exc:  # a field over the csv module's limit (128 KiB): no measured curve
        raise SceneError(f"{path.name} row {reader.line_num}: not a CSV table of numbers ({exc})") from None


def read_columns(path: Path, wanted: dict[str, str]) -> dict[str, np.ndarray]:
    """The named columns ({key: header name}) of a CSV as floats, every cell checked; "_line"
    holds each row's line number in the file (the header is line 1)."""
    rows = [(i + 1, r) for i, r in enumerate(_csv_rows(path)) if any(c.strip() for c in r)]
    if not rows:
        raise SceneError(f"{path.name} is empty: expected a header row naming the columns "
                         f"{', '.join(repr(v) for v in wanted.values())}")
    header = [h.strip() for h in rows[0][1]]
    cols = {key: header.index(name) for key, name in wanted.items() if name in header}
    for key, name in wanted.items():
        if key not in cols:
            raise SceneError(_missing_column(path, key, name, header, bool(cols)))
    if len(rows) < 2:
        raise SceneError(f"{path.name} has a header but no data rows")
    out = {k: [] for k in wanted} | {"_line": []}
    for line, r in rows[1:]:
        out["_line"].append(line)
        for key, j in cols.items():
            text = r[j].strip() if j < len(r) else ""
            if not text:
                raise SceneError(f"{path.name} row {line} column {wanted[key]!r}: empty cell")
            out[key].append(_cell(path, line, wanted[key], text))
    return {k: np.array(v) for k, v in out.items()}


STRESS_RANGE = (1e-9, 1e6)   # MPa: the largest |stress| of a data set (1 mPa .. 1 TPa, beyond any solid)
SOFTENING = 0.10             # a fall of the stress by more than this share of its largest |value| is softening
WRONG_SIGN = 0.02            # a stress of the wrong sign larger than this share of the largest is not noise
_MONOTONIC = ("uniaxial", "equibiaxial", "planar", "simple-shear", "confined-compression")


def check_plausible(path: Path, kind: str, column: str, a: np.ndarray, y: np.ndarray, lines) -> None:
    """Data no card of the library can represent, named before any fit (SceneError, exit 2):
    a largest |stress| outside STRESS_RANGE (a unit error, or no load at all); in a monotonic kind,
    a nominal or true stress whose sign is not that of the deformation (λ − 1, or γ) or that falls
    as the stretch rises (softening: a hyperelastic card with dP/dλ < 0 is Drucker-unstable)."""
    top = float(np.max(np.abs(y)))
    lo, hi = STRESS_RANGE
    if not lo <= top <= hi:
        j = int(np.argmax(np.abs(y)))
        raise SceneError(f"{path.name} row {int(lines[j])}: the largest |stress| is {top:g} MPa, outside the "
                         f"plausible range {lo:g}..{hi:g} MPa (check data[].units and the column)")
    if kind not in _MONOTONIC:
        return
    ref = 0.0 if kind == "simple-shear" else 1.0
    name = "shear" if kind == "simple-shear" else "stretch"
    bad = np.nonzero(np.sign(a - ref) * y < -WRONG_SIGN * top)[0]
    if len(bad):
        j = int(bad[0])
        raise SceneError(f"{path.name} row {int(lines[j])}: stress {y[j]:g} MPa at {name} {a[j]:g} has the "
                         f"sign opposite to the deformation ({'tension' if a[j] > ref else 'compression'}): "
                         "not a loading curve of this kind (check the sign convention and the kind)")
    order = np.argsort(a)
    ya = y[order]
    peak = np.maximum.accumulate(ya)
    drop = peak - ya
    if np.any(drop > SOFTENING * top):
        k = int(np.argmax(drop > SOFTENING * top))
        j, i = int(order[k]), int(order[int(np.argmax(ya[:k + 1]))])
        raise SceneError(f"{path.name} row {int(lines[j])}: the stress falls to {y[j]:g} MPa at {name} {a[j]:g} "
                         f"from {y[i]:g} MPa at {name} {a[i]:g} ({100 * drop[k] / top:.3g} % of the largest "
                         f"|stress|): softening (damage, Mullins, an unloading branch) is not a hyperelastic "
                         f"{kind} curve, no stable card of the library follows it; fit the loading branch "
                         "up to its peak")


def check_monotonic(path: Path, column: str, v: np.ndarray, lines: np.ndarray) -> None:
    """A controlled stretch/shear must run one way (a loading curve, not a loop)."""
    d = np.diff(v)
    bad = np.nonzero(d <= 0)[0] if np.sum(d > 0) >= np.sum(d < 0) else np.nonzero(d >= 0)[0]
    if len(v) > 1 and len(bad):
        i = int(bad[0]) + 1
        raise SceneError(f"{path.name} row {int(lines[i])} column {column!r}: {v[i]:g} after {v[i - 1]:g} — "
                         "the stretch must be strictly monotonic (one loading branch)")
