"""A misaligned load train: the moving grip of a uniaxial test in clamped grips is offset and tilted.

``[test] misalignment = {offset = [e_y, e_z], tilt = [θ_y, θ_z]}``: at the end of the travel (load
parameter t = 1) the moving clamp (its nodes; x_c their smallest x, the clamp's edge where the
free length begins, y_c and z_c their mid-width and mid-thickness) has, besides its travel Δ
along x,

- moved by e = (0, e_y, e_z) (the load axis is offset from the fixed grip's along the width y and
  the thickness z), and
- turned rigidly about the point X_c = (x_c, y_c, z_c) by R = R_xy(θ_z) R_xz(θ_y): first by θ_y in
  the x–z plane (bending through the thickness), then by θ_z in the x–y plane (bending across the
  width), so that the axis of the clamped end points along
  (cos θ_z cos θ_y, sin θ_z cos θ_y, sin θ_y):

    u = Δ e_x + e + (R − I)(X − X_c),
    R_xz(θ) = [[cos θ, 0, −sin θ], [0, 1, 0], [sin θ, 0, cos θ]],
    R_xy(θ) = [[cos θ, −sin θ, 0], [sin θ, cos θ, 0], [0, 0, 1]]

(θ_z = e_y = 0: u_x = Δ + (cos θ − 1)(x − x_c) − sin θ (z − z_c), u_z = e_z + sin θ (x − x_c) +
(cos θ − 1)(z − z_c), the thickness plane alone).

Like the travel, the misalignment is prescribed in proportion to t (u_p(t) = t · û_p, the
rotation linearised between 0 and 1: exact at t = 1 and off a rigid turn by O(θ²) in between): a
load train whose lateral compliance lets the grip drift and turn as the force rises, so that the
bending grows with the axial strain and the percent bending (vlab.measure.bending) is the same at
every load level. The fixed grip holds.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["misalign", "rotation"]


def rotation(tilt_y_deg: float, tilt_z_deg: float) -> np.ndarray:
    """R = R_xy(θ_z) R_xz(θ_y) (module docstring), 3 × 3."""
    cy, sy = math.cos(math.radians(tilt_y_deg)), math.sin(math.radians(tilt_y_deg))
    cz, sz = math.cos(math.radians(tilt_z_deg)), math.sin(math.radians(tilt_z_deg))
    r_xz = np.array([[cy, 0.0, -sy], [0.0, 1.0, 0.0], [sy, 0.0, cy]])
    r_xy = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    return r_xy @ r_xz


def misalign(u_hat: np.ndarray, X: np.ndarray, dofs_x: np.ndarray, offset_y: float, offset_z: float,
             tilt_y_deg: float, tilt_z_deg: float) -> np.ndarray:
    """û with the moving grip's lateral component and turn added (module docstring); ``dofs_x``
    the grip's x DOFs (3 node + 0, a 3D mesh). A copy; û itself is left alone."""
    out = u_hat.copy()
    nodes = dofs_x // 3
    P = X[nodes]
    centre = np.array([P[:, 0].min(), 0.5 * (P[:, 1].min() + P[:, 1].max()), 0.5 * (P[:, 2].min() + P[:, 2].max())])
    turn = (P - centre) @ (rotation(tilt_y_deg, tilt_z_deg) - np.eye(3)).T
    for k, e in enumerate((0.0, offset_y, offset_z)):
        out[3 * nodes + k] += e + turn[:, k]
    return out
