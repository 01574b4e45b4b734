"""Gent: ψ = −(μ Jm / 2) ln(1 − (Ī₁ − 3)/Jm) + U(J), μ0 = μ.

μ (MPa) and Jm (dimensionless, the largest Ī₁ − 3 the chains allow). With x = Ī₁ − 3,
y = 1 − x/Jm: W₁ = μ/(2y), W₁₁ = μ/(2 Jm y²); P and A from vlab.materials.invariant.
Locking: at x ≥ Jm the energy is +inf (and P, A nan), so the solver's line search treats such a
state as inadmissible, and the homogeneous oracle and the scene check name the stretch at which
the test reaches Ī₁ − 3 = Jm (``locking_note``). Jm → ∞ gives Neo-Hookean with μ.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.invariant import InvariantModel

__all__ = ["Gent"]


@dataclass(frozen=True, kw_only=True)
class Gent(InvariantModel):
    modulus: float  # μ, MPa (card key mu; the name mu is the shear modulus μ0 of every model)
    Jm: float

    name: ClassVar[str] = "gent"

    @property
    def mu0(self) -> float:
        return float(self.modulus)

    @property
    def locking_note(self) -> str:
        return f"the Gent chains lock at Ī1 − 3 = Jm = {self.Jm:g}"

    def W(self, x1, x2):
        mu, Jm = self.modulus, self.Jm
        x1 = np.asarray(x1, dtype=float)
        y = np.where(x1 < Jm, 1.0 - x1 / Jm, np.nan)  # nan past the locking limit: W = +inf
        with np.errstate(all="ignore"):
            W = np.where(np.isnan(y), np.inf, -0.5 * mu * Jm * np.log1p(-x1 / Jm))
        return (W, 0.5 * mu / y, 0.0, 0.5 * mu / (Jm * y * y), 0.0, 0.0)
