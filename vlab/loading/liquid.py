"""The liquid under a wetted face, as a load specification (the bulge tester's chamber, a
balloon's gas): which face, which control, its target. The body that applies it — the enclosed
volume, the pressure's work and its tangent — is vlab.fe.liquid.LiquidBody (its docstring has
the formulas)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Liquid"]


@dataclass(frozen=True)
class Liquid:
    """The chamber under a wetted face: ``triangles`` (n, 3) node indices, counter-clockwise seen
    from the liquid; ``control`` "volume" (``target`` = V_p(1), mm³, ``stiffness`` k = K_f / V₀,
    MPa/mm³) or "pressure" (``target`` = p*, MPa)."""

    triangles: np.ndarray
    control: str
    target: float
    stiffness: float = 0.0

    def pressure(self, t: float, volume: float) -> float:
        """p (MPa) at load parameter t with the enclosed volume ``volume`` (module docstring)."""
        if self.control == "pressure":
            return t * self.target
        return self.stiffness * (t * self.target - volume)
