"""Prescribed displacements of a torsion test on a cylinder along x (vlab.loading.kinds.torsion).

The grip x = 0 clamps its end face (u = 0). The grip x = L turns its end face rigidly about the
axis by φ(t) = t ψ L (ψ the final twist per unit length, rad/mm):

    u_y = y (cos φ − 1) − z sin φ,   u_z = y sin φ + z (cos φ − 1)

and, along the axis, ``fixed`` holds u_x = 0 (the length is held: the load cell reads the axial
force N) or ``free`` leaves each node's u_x free (the end face slides along the axis without
friction: zero axial traction, and the length change is read). Not proportional to t: the
loading's ``path`` gives u_p(t) and ``u_hat`` is its rate at t = 0, ψ L (−z, y).

Tension–torsion (an axial stretch λ₀ ≠ 1, length held): the turning end moves along the axis by
(λ(t) − 1) L, and both end faces contract by s(t) = λ(t)^(−1/2), as an incompressible cylinder's
sections do, so that the grips impose the state Rivlin's solution assumes (sections that stay
plane and contract uniformly) instead of clamping the ends at their initial radius:

    u_x = (λ(t) − 1) L (x = L),  (y, z) ↦ s(t) R(φ(t)) (y, z) (x = L),  s(t) (y, z) (x = 0).

The order (``tension_torsion``): "stretch-then-twist" (a lab's: the stretch first, then the twist
at the held stretch) runs λ(t) = 1 + (t/t₁)(λ₀ − 1), φ = 0 for t ≤ t₁ = PHASE_END, then λ₀ and
φ(t) = ψ L (t − t₁)/(1 − t₁); "together" ramps both, λ(t) = 1 + t (λ₀ − 1), φ(t) = t ψ L. For an
elastic card both end in the same state; the paths differ.
"""

from __future__ import annotations

import numpy as np

from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading

__all__ = ["PHASE_END", "tension_torsion", "torsion_loading"]

PHASE_END = 0.5  # the load parameter t₁ where a stretch-then-twist test's stretch phase ends


def tension_torsion(stretch: float, twist: float, t: float, phased: bool) -> tuple[float, float]:
    """(λ(t), ψ(t)): the axial stretch and the twist (rad/mm) at load parameter t, the stretch
    first (``phased``, up to t₁ = PHASE_END) or both together (module docstring)."""
    if not phased:
        return 1.0 + t * (stretch - 1.0), t * twist
    if t <= PHASE_END:
        return 1.0 + (t / PHASE_END) * (stretch - 1.0), 0.0
    return stretch, twist * (t - PHASE_END) / (1.0 - PHASE_END)


def torsion_loading(specimen: Specimen, X: np.ndarray, twist: float, axial: str,
                    stretch: float = 1.0, phased: bool = False) -> GripLoading:
    """The clamped and the turning end, with the axial stretch ``stretch`` applied first
    (``phased``) or with the twist (module docstring)."""
    fixed, moving = specimen.grips_on(0)
    low, high = np.flatnonzero(fixed.select(X)), np.flatnonzero(moving.select(X))
    length = specimen.grip_separation[0]
    y, z = X[high, 1], X[high, 2]
    comps = (0, 1, 2) if axial == "fixed" else (1, 2)
    prescribed = np.unique(np.concatenate([3 * low + c for c in range(3)] + [3 * high + c for c in comps]))

    def path(t: float) -> np.ndarray:
        lam, psi = tension_torsion(stretch, twist, t, phased)
        phi, s = psi * length, lam**-0.5
        u = np.zeros(3 * len(X))
        u[3 * high] = (lam - 1.0) * length
        u[3 * high + 1] = s * (y * np.cos(phi) - z * np.sin(phi)) - y
        u[3 * high + 2] = s * (y * np.sin(phi) + z * np.cos(phi)) - z
        u[3 * low + 1] = (s - 1.0) * X[low, 1]
        u[3 * low + 2] = (s - 1.0) * X[low, 2]
        return u

    # du_p/dt at t = 0: dλ/dt = (λ₀ − 1)/t₁ and no twist in a phased test's stretch phase
    rate, angle = ((stretch - 1.0) / PHASE_END, 0.0) if phased else (stretch - 1.0, twist * length)
    u_hat = np.zeros(3 * len(X))
    u_hat[3 * high] = rate * length
    u_hat[3 * high + 1] = -angle * z - 0.5 * rate * y
    u_hat[3 * high + 2] = angle * y - 0.5 * rate * z
    u_hat[3 * low + 1] = -0.5 * rate * X[low, 1]
    u_hat[3 * low + 2] = -0.5 * rate * X[low, 2]
    return GripLoading(prescribed.astype(np.int64), u_hat, {0: 3 * high}, path)
