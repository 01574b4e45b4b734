"""The columns of a specimen data set (``kind = "specimen"``), by the test kind of the fit's [fe]
scene (vlab.identify.fe_readings.SPECIMEN_KINDS): which keys ``columns`` may name, which channels
they make, and the Dataset they read into.

Per channel the data give one control column (default: the channel's first) and one reading
column (default: the first reading of a required channel; an optional channel is there when the
data name one of its readings). ``a`` holds the first channel's control, ``b`` the second's (None
with one channel), ``y`` the readings channel after channel, ``extra["channels"]`` the
(control key, reading key) pairs. A control given as ``strain`` is read as the stretch 1 + strain.
``units`` scales every reading that shares the first reading's unit table (a cruciform's two load
cells); the others are read in the solver's units (N, 1). Errors name the column key, the scene's
kind and what it records (exit 2).
"""

from __future__ import annotations

import numpy as np

from vlab import fields
from vlab.fields import SceneError, Table

__all__ = ["specimen_dataset", "column_keys"]


def column_keys(kind) -> tuple[str, ...]:
    """Every column key a specimen data set of this kind may name."""
    out = []
    for c in kind.channels:
        for q in c.controls + c.readings:
            out += [q.key] + (["strain"] if q.strain_alias else [])
    return tuple(dict.fromkeys(out))


def _pick(ct: Table, options, scene, kind_name: str, default: bool):
    """(quantity, the key given) of the one option the columns name (or the first, by default)."""
    given = [(q, k) for q in options for k in (q.key, "strain") if k in ct.raw and (k == q.key or q.strain_alias)]
    keys = list(dict.fromkeys(k for _, k in given))
    if len(keys) > 1:
        raise SceneError(f"{ct.field(keys[1])}: give one of {', '.join(keys)} for test.kind {kind_name!r}, not both")
    if not given:
        if not default:
            return None, None
        q = next((q for q in options if q.needs(scene) is None), options[0])
        return q, q.key
    fits = [(q, k) for q, k in given if q.needs(scene) is None]
    if not fits:
        raise SceneError(f"{ct.field(given[0][1])}: {given[0][0].needs(scene)} (fe.scene's specimen is a "
                         f"{scene.specimen.shape}, test.kind {kind_name!r})")
    return fits[0]


def _channels(ct: Table, kind, scene) -> list[tuple]:
    """[(control quantity, its key, reading quantity, its key)] of the channels the columns make."""
    out = []
    for i, ch in enumerate(kind.channels):
        reading, rkey = _pick(ct, ch.readings, scene, kind.name, not ch.optional)
        if reading is None:
            lonely = [q.key for q in ch.controls if q.key in ct.raw and all(
                q.key not in [c.key for c in other.controls] for other in kind.channels[:i])]
            if lonely:
                raise SceneError(f"{ct.field(lonely[0])} needs its reading too: columns."
                                 f"{' or columns.'.join(q.key for q in ch.readings)}")
            continue
        control, ckey = _pick(ct, ch.controls, scene, kind.name, True)
        if control.needs(scene) is not None:
            raise SceneError(f"{ct.field(control.key)}: {control.needs(scene)}")
        out.append((control, ckey, reading, rkey))
    return out


def _columns_table(t: Table, kind, scene) -> Table:
    raw = t.get("columns", {})
    allowed = column_keys(kind)
    if not isinstance(raw, dict):
        raise SceneError(f"{t.field('columns')} must be a table {{ key = \"<CSV header>\" }}, got {fields.show(raw)}")
    for key in raw:
        if key not in allowed:
            raise SceneError(f"{t.field('columns')}.{key}: a specimen data set of fe.scene's test.kind "
                             f"{kind.name!r} has no column {key!r} (allowed: {', '.join(allowed)})"
                             f"{fields.suggest(key, allowed)}")
    return Table(t.field("columns"), raw, allowed)


def specimen_dataset(t: Table, file: str, base, scene, weight_max: float):
    """The Dataset of one [[data]] table of kind "specimen" read against the scene's kind."""
    from pathlib import Path

    from vlab.identify.datasets import Dataset, check_monotonic, read_columns
    from vlab.identify.fe_readings import SPECIMEN_KINDS

    kind = SPECIMEN_KINDS[scene.test.kind]
    ct = _columns_table(t, kind, scene)
    chans = _channels(ct, kind, scene)
    first = chans[0][2].units
    unit = t.choice("units", tuple(first), next(iter(first)))
    t.choice("stress_measure", ("nominal", "true"), "nominal")  # a specimen's readings are not stresses
    role = t.choice("role", ("fit", "validate"), "fit")
    weight = t.number("weight", 1.0, gt=0, le=weight_max, note=" (relative to the other data sets)")
    name = t.get("name", Path(file).stem)
    wanted = {k: ct.raw.get(k, k) for _, ck, _, rk in chans for k in (ck, rk)}
    for k, v in wanted.items():
        if not isinstance(v, str) or not v:
            raise SceneError(f"{ct.field(k)} must be a column name (string), got {fields.show(v)}")
    path = (base / file).resolve()
    cols = read_columns(path, wanted)
    lines = cols.pop("_line")
    controls, readings = [], []
    for control, ckey, reading, rkey in chans:
        x = cols[ckey] + (1.0 if ckey == "strain" and control.key != "strain" else 0.0)
        check_monotonic(path, wanted[ckey], x, lines)
        controls.append(x)
        readings.append(cols[rkey] * (first[unit] if reading.units is first else 1.0))
    return Dataset(str(name), str(path), "specimen", role, weight, "nominal", controls[0],
                   controls[1] if len(controls) > 1 else None, np.concatenate(readings),
                   {"channels": tuple((c.key, r.key) for c, _, r, _ in chans)})
