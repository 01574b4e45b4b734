"""The contract of a closed-form data kind of `vlab fit` (one module per kind in
vlab.identify.kinds.FIT_KINDS), and what the kinds share: Gauss–Legendre rules that keep a
prediction analytic in the card (complex step), and the [data.geometry] table.

A kind is a ``FitKind``:

- ``name``: the ``[[data]] kind``; ``columns``: (required, optional) column keys; ``control``: the
  column the curve runs along (strictly monotonic);
- ``geometry``: {key: meaning} of the required ``[data.geometry]`` lengths (mm, > 0);
  ``geometry_limits``: {key: (unit, lo, hi)} for a geometry entry that is not a length (the
  pre-stretch of tension–torsion: dimensionless, lo ≤ value ≤ hi);
- ``units`` ({name: factor to the kind's unit}) and ``default_unit``; ``measures``: the
  ``stress_measure`` values that apply (empty: the key is refused);
- ``compressible``: the kind is meaningless for an incompressible card (it fixes K);
- ``build(path, cols, wanted, lines, factor, geometry)`` → (a, b, y, extra), every check done;
- ``predict(model, X, d)`` → (m, len(d.y)) at internal coordinates X (m, n_x), analytic in X;
- ``max_I1(d)``: the largest I1 the data reach (the starts' bounds, e.g. Gent's Jm);
- ``labels``: (x label, y label of each output, in the order of ``d.extra["outputs"]``);
- ``states(d)``: principal stretches (3, k) of material points the data reach (at the data's own
  twists, stretches, ...), where vlab.identify.drucker.states_stability judges the fitted card.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from vlab.fields import SceneError, Table

__all__ = ["FitKind", "gauss", "parse_geometry"]


@dataclass(frozen=True)
class FitKind:
    name: str
    columns: tuple[tuple[str, ...], tuple[str, ...]]
    control: str
    geometry: dict
    units: dict
    default_unit: str
    measures: tuple[str, ...]
    compressible: bool
    build: Callable
    predict: Callable
    max_I1: Callable
    labels: tuple
    geometry_limits: dict = field(default_factory=dict)
    states: Callable | None = None


def gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [0, 1] (exact for polynomials of degree 2n − 1)."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def parse_geometry(t: Table, kind: FitKind) -> dict:
    """{key: mm} of ``[data.geometry]`` for a kind that needs lengths; a missing table or key is a
    SceneError naming the field and what it is; a kind without geometry refuses the table."""
    if not kind.geometry:
        if "geometry" in t.raw:
            raise SceneError(f"{t.field('geometry')}: kind = {kind.name!r} takes no geometry (a homogeneous "
                             "state: the data are stresses already)")
        return {}
    need = ", ".join(f"{k} ({v})" for k, v in kind.geometry.items())
    if "geometry" not in t.raw:
        raise SceneError(f"{t.field('geometry')} is required for kind = {kind.name!r}: [data.geometry] with {need}")
    g = Table(t.field("geometry"), t.raw["geometry"], tuple(kind.geometry))
    out = {}
    for key, meaning in kind.geometry.items():
        if key not in g.raw:
            raise SceneError(f"{g.field(key)} is required for kind = {kind.name!r}: {meaning}")
        if key in kind.geometry_limits:
            unit, lo, hi = kind.geometry_limits[key]
            out[key] = g.number(key, ge=lo, le=hi, note=f" ({unit}, {meaning})")
        else:
            out[key] = g.number(key, gt=0, note=f" (mm, {meaning})")
    return out


def outputs_of(d) -> tuple[str, ...]:
    """The names of the blocks of d.y (one per output, each as long as d.a)."""
    return tuple((d.extra or {}).get("outputs", ("stress",)))


def floor_of(d) -> np.ndarray:
    """Per point, 1 % of the largest |y| of its output block (a torque and an axial force in
    their own units each get their own floor): the relative residual's denominator floor."""
    blocks = np.split(np.abs(np.asarray(d.y, float)), len(outputs_of(d)))
    return np.concatenate([np.full(len(b), 0.01 * np.max(b)) for b in blocks])
