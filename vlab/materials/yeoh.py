"""Yeoh: ψ = C10 (Ī₁ − 3) + C20 (Ī₁ − 3)² + C30 (Ī₁ − 3)³ + U(J), μ0 = 2 C10.

C10, C20, C30 in MPa (Abaqus' names). With x = Ī₁ − 3: W₁ = C10 + 2 C20 x + 3 C30 x²,
W₁₁ = 2 C20 + 6 C30 x; P and A from vlab.materials.invariant.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from vlab.materials.invariant import InvariantModel

__all__ = ["Yeoh"]


@dataclass(frozen=True, kw_only=True)
class Yeoh(InvariantModel):
    C10: float
    C20: float = 0.0
    C30: float = 0.0

    name: ClassVar[str] = "yeoh"

    @property
    def mu0(self) -> float:
        return 2.0 * self.C10

    def W(self, x1, x2):
        c1, c2, c3 = self.C10, self.C20, self.C30
        W = x1 * (c1 + x1 * (c2 + x1 * c3))
        return (W, c1 + x1 * (2.0 * c2 + 3.0 * c3 * x1), 0.0, 2.0 * c2 + 6.0 * c3 * x1, 0.0, 0.0)
