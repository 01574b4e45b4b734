"""A misaligned load train: the moving grip of a uniaxial test in clamped grips is offset and tilted.

``[test] misalignment = {offset = e, tilt = θ}``: at the end of the travel (load parameter t = 1)
the moving clamp (its nodes; x_c their smallest x, the clamp's edge where the free length begins,
z_c their mid-thickness) has, besides its travel Δ along x,

- moved by e along z (the thickness: the load axis is offset from the fixed grip's by e), and
- turned rigidly by θ about the y axis through (x_c, z_c), so that the axis of the clamped end
  points along (cos θ, 0, sin θ) (the load axis is tilted by θ):

    u_x = Δ + (cos θ − 1)(x − x_c) − sin θ (z − z_c),   u_z = e + sin θ (x − x_c) + (cos θ − 1)(z − z_c)

Like the travel, the misalignment is prescribed in proportion to t (u_p(t) = t · û_p, the
rotation linearised between 0 and 1: exact at t = 1 and off a rigid turn by O(θ²) in between): a
load train whose lateral compliance lets the grip drift and turn as the force rises, so that the
bending grows with the axial strain and the percent bending (vlab.measure.bending) is the same at
every load level. The fixed grip holds.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["misalign"]


def misalign(u_hat: np.ndarray, X: np.ndarray, dofs_x: np.ndarray, offset: float, tilt_deg: float) -> np.ndarray:
    """û with the moving grip's lateral component and turn added (module docstring); ``dofs_x``
    the grip's x DOFs (3 node + 0, a 3D mesh). A copy; û itself is left alone."""
    out = u_hat.copy()
    nodes = dofs_x // 3
    x, z = X[nodes, 0] - X[nodes, 0].min(), X[nodes, 2] - 0.5 * (X[nodes, 2].min() + X[nodes, 2].max())
    c, s = math.cos(math.radians(tilt_deg)) - 1.0, math.sin(math.radians(tilt_deg))
    out[3 * nodes] += c * x - s * z
    out[3 * nodes + 2] += offset + s * x + c * z
    return out
