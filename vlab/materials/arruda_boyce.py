"""Arruda–Boyce (eight-chain), the five-term series: ψ = μ Σᵢ Cᵢ/λm^(2i−2) (Ī₁^i − 3^i) + U(J).

C = (1/2, 1/20, 11/1050, 19/7000, 519/673750); μ (MPa) and the locking stretch λm > 1
(Abaqus' ``lambda_m``). W₁ = μ Σ i Cᵢ Ī₁^(i−1)/λm^(2i−2), W₁₁ = μ Σ i(i−1) Cᵢ Ī₁^(i−2)/λm^(2i−2);
the energy is summed as the polynomial in x = Ī₁ − 3 (no cancellation of Ī₁^i − 3^i).
μ0 = 2 W₁(3) = μ (1 + 3/(5λm²) + 99/(175λm⁴) + 513/(875λm⁶) + 42039/(67375λm⁸)).

1 < λm <= LAMBDA_M_MAX = 1e6: λm → ∞ is Neo-Hookean with μ, and at 1e6 the series' corrections
(3/(5λm²) = 6e-13 of μ0) are already below the energy's rounding, while λm⁸ overflows double
precision near 1e38 (a scene with λm = 1e200 raised OverflowError while it was read).
"""

from __future__ import annotations

from dataclasses import dataclass
from math import comb
from typing import ClassVar

from vlab.materials.invariant import InvariantModel

__all__ = ["ArrudaBoyce", "LAMBDA_M_MAX", "SERIES"]

LAMBDA_M_MAX = 1e6
SERIES = (1.0 / 2.0, 1.0 / 20.0, 11.0 / 1050.0, 19.0 / 7000.0, 519.0 / 673750.0)


@dataclass(frozen=True, kw_only=True)
class ArrudaBoyce(InvariantModel):
    modulus: float  # μ, MPa (card key mu)
    lambda_m: float

    name: ClassVar[str] = "arruda-boyce"

    def _c(self) -> list[float]:
        """μ Cᵢ/λm^(2i−2), i = 1..5, MPa."""
        return [self.modulus * c / self.lambda_m ** (2 * i) for i, c in enumerate(SERIES)]

    @property
    def mu0(self) -> float:
        return 2.0 * sum((i + 1) * c * 3.0 ** i for i, c in enumerate(self._c()))

    def W(self, x1, x2):
        c = self._c()
        I1 = 3.0 + x1
        W = sum(ci * sum(comb(i + 1, k) * 3.0 ** (i + 1 - k) * x1 ** k for k in range(1, i + 2))
                for i, ci in enumerate(c))
        W1 = sum((i + 1) * ci * I1 ** i for i, ci in enumerate(c))
        W11 = sum((i + 1) * i * ci * I1 ** (i - 1) for i, ci in enumerate(c) if i > 0)
        return (W, W1, 0.0, W11, 0.0, 0.0)
