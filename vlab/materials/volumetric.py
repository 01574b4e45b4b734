"""Volumetric energies U(J) of the split models, written in the volume change x = J − 1.

K is the small-strain bulk modulus (MPa): every U here has U(1) = U'(1) = 0 and U''(1) = K.
Each function takes x (not J) so that U = K/2 x² keeps full relative precision for tiny x
(the energy line search and the mixed body's θ − 1 need it, see vlab.materials.split).

- ``quadratic``   U = K/2 (J − 1)²           U' = K (J − 1)           U'' = K         (Abaqus' default)
- ``log``         U = K/2 (ln J)²            U' = K ln J / J          U'' = K (1 − ln J)/J²
- ``simo-taylor`` U = K/4 (J² − 1 − 2 ln J)  U' = K/2 (J − 1/J)       U'' = K/2 (1 + 1/J²)

The log and Simo–Taylor forms are +inf at J ≤ 0 (J → 0⁺ costs infinite energy); the quadratic
one is finite there, but every isochoric part on C̄ = J^(−2/3) C is +inf at J ≤ 0, so no model
admits an inverted state. ``log`` is not convex beyond J = e (U'' < 0): a volume that grows by
172 % is outside any rubber test.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["Volumetric", "VOLUMETRIC", "VOLUMETRIC_NAMES"]


@dataclass(frozen=True)
class Volumetric:
    """U, U', U'' per unit K as functions of x = J − 1 (arrays), MPa/MPa."""

    name: str
    formula: str
    U: Callable[[np.ndarray], np.ndarray]
    dU: Callable[[np.ndarray], np.ndarray]
    d2U: Callable[[np.ndarray], np.ndarray]


def _inadmissible(f):
    """f(x) where J = 1 + x > 0, +inf (energy) or nan (derivatives) elsewhere, no warnings."""
    def wrapped(x, bad=np.inf):
        x = np.asarray(x, dtype=float)
        ok = x > -1.0
        with np.errstate(all="ignore"):
            return np.where(ok, f(np.where(ok, x, 0.0)), bad)
    return wrapped


def _quadratic() -> Volumetric:
    return Volumetric("quadratic", "K/2 (J − 1)²", lambda x: 0.5 * np.asarray(x) ** 2,
                      lambda x: np.asarray(x, dtype=float) * 1.0, lambda x: np.ones(np.shape(x)))


def _log() -> Volumetric:
    U = _inadmissible(lambda x: 0.5 * np.log1p(x) ** 2)
    dU = _inadmissible(lambda x: np.log1p(x) / (1.0 + x))
    d2U = _inadmissible(lambda x: (1.0 - np.log1p(x)) / (1.0 + x) ** 2)
    return Volumetric("log", "K/2 (ln J)²", U, lambda x: dU(x, np.nan), lambda x: d2U(x, np.nan))


def _simo_taylor() -> Volumetric:
    U = _inadmissible(lambda x: 0.25 * (x * (2.0 + x) - 2.0 * np.log1p(x)))
    dU = _inadmissible(lambda x: 0.5 * x * (2.0 + x) / (1.0 + x))
    d2U = _inadmissible(lambda x: 0.5 * (1.0 + 1.0 / (1.0 + x) ** 2))
    return Volumetric("simo-taylor", "K/4 (J² − 1 − 2 ln J)", U, lambda x: dU(x, np.nan),
                      lambda x: d2U(x, np.nan))


#: material.volumetric -> its U(J); the first is the default
VOLUMETRIC: dict[str, Volumetric] = {v.name: v for v in (_quadratic(), _log(), _simo_taylor())}
VOLUMETRIC_NAMES = tuple(VOLUMETRIC)
