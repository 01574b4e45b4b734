"""Prescribed displacements of a torsion test on a cylinder along x (vlab.loading.kinds.torsion).

The grip x = 0 clamps its end face (u = 0). The grip x = L turns its end face rigidly about the
axis by φ(t) = t ψ L (ψ the final twist per unit length, rad/mm):

    u_y = y (cos φ − 1) − z sin φ,   u_z = y sin φ + z (cos φ − 1)

and, along the axis, ``fixed`` holds u_x = 0 (the length is held: the load cell reads the axial
force N) or ``free`` leaves each node's u_x free (the end face slides along the axis without
friction: zero axial traction, and the length change is read). Not proportional to t: the
loading's ``path`` gives u_p(t) and ``u_hat`` is its rate at t = 0, ψ L (−z, y).
"""

from __future__ import annotations

import numpy as np

from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading

__all__ = ["torsion_loading"]


def torsion_loading(specimen: Specimen, X: np.ndarray, twist: float, axial: str) -> GripLoading:
    """The clamped and the turning end (module docstring)."""
    fixed, moving = specimen.grips_on(0)
    low, high = np.flatnonzero(fixed.select(X)), np.flatnonzero(moving.select(X))
    angle = twist * specimen.grip_separation[0]  # total at t = 1, rad
    y, z = X[high, 1], X[high, 2]
    comps = (0, 1, 2) if axial == "fixed" else (1, 2)
    prescribed = np.unique(np.concatenate([3 * low + c for c in range(3)] + [3 * high + c for c in comps]))

    def path(t: float) -> np.ndarray:
        phi = t * angle
        u = np.zeros(3 * len(X))
        u[3 * high + 1] = y * (np.cos(phi) - 1.0) - z * np.sin(phi)
        u[3 * high + 2] = y * np.sin(phi) + z * (np.cos(phi) - 1.0)
        return u

    u_hat = np.zeros(3 * len(X))
    u_hat[3 * high + 1], u_hat[3 * high + 2] = -angle * z, angle * y
    return GripLoading(prescribed.astype(np.int64), u_hat, {0: 3 * high}, path)
