"""Prescribed displacements of a torsion test on a cylinder along x (vlab.loading.kinds.torsion).

The grip x = 0 clamps its end face (u = 0). The grip x = L turns its end face rigidly about the
axis by φ(t) = t ψ L (ψ the final twist per unit length, rad/mm):

    u_y = y (cos φ − 1) − z sin φ,   u_z = y sin φ + z (cos φ − 1)

and, along the axis, ``fixed`` holds u_x = 0 (the length is held: the load cell reads the axial
force N) or ``free`` leaves each node's u_x free (the end face slides along the axis without
friction: zero axial traction, and the length change is read). Not proportional to t: the
loading's ``path`` gives u_p(t) and ``u_hat`` is its rate at t = 0, ψ L (−z, y).

Tension–torsion (an axial stretch λ₀ ≠ 1, length held): with the twist, the turning end moves
along the axis by t (λ₀ − 1) L, and both end faces contract by s(t) = λ(t)^(−1/2),
λ(t) = 1 + t (λ₀ − 1), as an incompressible cylinder's sections do, so that the grips impose the
state Rivlin's solution assumes (sections that stay plane and contract uniformly) instead of
clamping the ends at their initial radius:

    u_x = t (λ₀ − 1) L (x = L),  (y, z) ↦ s(t) R(φ(t)) (y, z) (x = L),  s(t) (y, z) (x = 0).
"""

from __future__ import annotations

import numpy as np

from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading

__all__ = ["torsion_loading"]


def torsion_loading(specimen: Specimen, X: np.ndarray, twist: float, axial: str,
                    stretch: float = 1.0) -> GripLoading:
    """The clamped and the turning end, with the axial stretch ``stretch`` (module docstring)."""
    fixed, moving = specimen.grips_on(0)
    low, high = np.flatnonzero(fixed.select(X)), np.flatnonzero(moving.select(X))
    length = specimen.grip_separation[0]
    angle = twist * length  # total at t = 1, rad
    y, z = X[high, 1], X[high, 2]
    comps = (0, 1, 2) if axial == "fixed" else (1, 2)
    prescribed = np.unique(np.concatenate([3 * low + c for c in range(3)] + [3 * high + c for c in comps]))

    def path(t: float) -> np.ndarray:
        phi, lam = t * angle, 1.0 + t * (stretch - 1.0)
        s = lam**-0.5
        u = np.zeros(3 * len(X))
        u[3 * high] = (lam - 1.0) * length
        u[3 * high + 1] = s * (y * np.cos(phi) - z * np.sin(phi)) - y
        u[3 * high + 2] = s * (y * np.sin(phi) + z * np.cos(phi)) - z
        u[3 * low + 1] = (s - 1.0) * X[low, 1]
        u[3 * low + 2] = (s - 1.0) * X[low, 2]
        return u

    u_hat = np.zeros(3 * len(X))  # du_p/dt at t = 0
    u_hat[3 * high] = (stretch - 1.0) * length
    u_hat[3 * high + 1] = -angle * z - 0.5 * (stretch - 1.0) * y
    u_hat[3 * high + 2] = angle * y - 0.5 * (stretch - 1.0) * z
    u_hat[3 * low + 1] = -0.5 * (stretch - 1.0) * X[low, 1]
    u_hat[3 * low + 2] = -0.5 * (stretch - 1.0) * X[low, 2]
    return GripLoading(prescribed.astype(np.int64), u_hat, {0: 3 * high}, path)
