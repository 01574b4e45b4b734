"""Mooney–Rivlin: ψ = C10 (Ī₁ − 3) + C01 (Ī₂ − 3) + U(J), μ0 = 2 (C10 + C01).

C10, C01 in MPa (Abaqus' names); U(J) and K from vlab.materials.isochoric. W₁ = C10,
W₂ = C01, all second derivatives zero; P and A from vlab.materials.invariant. C01 = 0 is the
split Neo-Hookean model with μ = 2 C10. Either constant may be negative as long as μ0 > 0.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from vlab.materials.invariant import InvariantModel

__all__ = ["MooneyRivlin"]


@dataclass(frozen=True, kw_only=True)
class MooneyRivlin(InvariantModel):
    C10: float
    C01: float

    name: ClassVar[str] = "mooney-rivlin"
    uses_I2: ClassVar[bool] = True

    @property
    def mu0(self) -> float:
        return 2.0 * (self.C10 + self.C01)

    def W(self, x1, x2):
        return (self.C10 * x1 + self.C01 * x2, self.C10, self.C01, 0.0, 0.0, 0.0)
