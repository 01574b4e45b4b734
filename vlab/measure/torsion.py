"""What a torsion test measures (vlab.loading.kinds.torsion).

Readings per level, from the turning end's nodes (the grip x = L; f their reactions, N; x = X + u
their current positions, mm):
- the torque about the axis T = Σ (y f_z − z f_y) (N·mm);
- the axial stretch 1 + ū_x / L, ū_x the mean axial displacement of the end's nodes (1 with the
  length held).
Constants over the modulus window (ψ in it, rad/mm; measure/fit.py): the torsional stiffness
k = dT/dψ (N·mm²) and G = k / J_p, J_p = A² / (2π) the polar moment of a disc of the meshed
section's area A (small strain: T = G J_p ψ).
"""

from __future__ import annotations

import math

import numpy as np

from vlab.measure.elastic_constants import ElasticConstants
from vlab.measure.fit import FitError, fit_line

__all__ = ["torque_readers", "torsion_constants"]


def torque_readers(space, specimen, loading, material) -> dict:
    """Readers of the torque (N·mm) and the axial stretch of the turning end (module docstring)."""
    nodes = loading.moving_dofs[0] // 3
    X = space.node_coordinates[nodes]
    length = specimen.grip_separation[0]

    def torque(level) -> float:
        u, f = level.evaluation.u, level.evaluation.f_int
        y, z = X[:, 1] + u[3 * nodes + 1], X[:, 2] + u[3 * nodes + 2]
        return float(np.sum(y * f[3 * nodes + 2] - z * f[3 * nodes + 1]))

    def axial_stretch(level) -> float:
        return 1.0 + float(np.mean(level.evaluation.u[3 * nodes])) / length

    return {"torque": torque, "axial_stretch": axial_stretch}


def torsion_constants(curve, window, method) -> ElasticConstants:
    """k and G over the window, and the readings at the end (module docstring)."""
    note = "torsion: E and nu are not measured; G = (dT/dpsi) / J_p over the modulus window (psi in rad/mm)"
    extra: dict = {"torsional_stiffness": None, "G": None}
    polar = curve.area0[0] ** 2 / (2.0 * math.pi)
    try:
        k_fit = fit_line(np.array(curve.stretch[0]), np.array(curve.extra["torque"]), window, method)
        extra |= {"torsional_stiffness": k_fit.slope, "torsional_stiffness_fit": k_fit.as_dict(),
                  "G": k_fit.slope / polar}
    except FitError as exc:
        note = f"G not measured: {exc}"
    if curve.t:
        extra |= {"twist_at_end": curve.stretch[0][-1], "torque_at_end": curve.extra["torque"][-1],
                  "axial_force_at_end": curve.force[0][-1], "axial_stretch_at_end": curve.extra["axial_stretch"][-1]}
    return ElasticConstants(None, None, None, None, [{"axis": "x", "G": extra["G"]}], note, extra)
