"""Euler buckling of a clamped–clamped strip with Timoshenko's shear correction (the oracle of
the buckling study).

A strip of length L (between the grips, mm), width b and thickness h (h ≤ b, bending about the
thin direction), Young's modulus E and shear modulus G = E / (2 (1 + ν)) (MPa):
    P_E  = 4 π² E I / L²,  I = b h³ / 12        (clamped–clamped Euler load, N)
    P_cr = P_E / (1 + P_E / (κ G A)),  A = b h,  κ = 5/6 (rectangle)
and the critical (small) strain ε_cr = P_cr / (E A) = π² h² / (3 L²) / (1 + P_E / (κ G A)).

Beam theory is a small-strain, one-dimensional model: it ignores the change of geometry before
buckling (the strip is shorter and, by Poisson's effect, thicker at ε_cr, which raises the load by
about ((1 + ν ε) / (1 − ε))²), the clamps that also stop the lateral expansion of the end
sections, and the nonlinearity of the material; all of these matter only for stubby strips.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

SHEAR_COEFFICIENT = 5.0 / 6.0  # κ of a rectangular section


@dataclass(frozen=True)
class EulerStrip:
    euler_load: float  # P_E, N
    critical_load: float  # P_cr with shear correction, N
    euler_strain: float  # P_E / (E A)
    critical_strain: float  # P_cr / (E A)
    current_geometry_strain: float  # ε_cr corrected for the pre-buckling change of L and h

    def as_dict(self) -> dict:
        return dict(self.__dict__)


def clamped_strip(length: float, width: float, thickness: float, E: float, nu: float,
                  kappa: float = SHEAR_COEFFICIENT) -> EulerStrip:
    """Critical load and strain of a clamped–clamped strip (see the module formulas)."""
    b, h = max(width, thickness), min(width, thickness)
    area, inertia = b * h, b * h**3 / 12.0
    G = E / (2.0 * (1.0 + nu))
    p_e = 4.0 * math.pi**2 * E * inertia / length**2
    p_cr = p_e / (1.0 + p_e / (kappa * G * area))
    eps = p_cr / (E * area)
    # the same strip at its pre-buckling state: length L (1 − ε), thickness h (1 + ν ε)
    current = eps
    for _ in range(20):
        current = eps * ((1.0 + nu * current) / (1.0 - current)) ** 2
    return EulerStrip(p_e, p_cr, p_e / (E * area), eps, current)
