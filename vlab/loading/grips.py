"""Grips turn a test into prescribed displacements u_p(t) = t · û_p on named regions.

- roller (frictionless) grips prescribe only the displacement along the pulling axis, so the
  faces under the grips may slide and contract freely; the remaining rigid-body modes are removed
  at single nodes (3-2-1 rule; on a 2D sheet one node's y in uniaxial tests) at points the
  homogeneous solution leaves in place.
- clamped grips prescribe all components (three, or two on a 2D sheet): the fixed grip holds, the moving grip translates
  along its axis. In a biaxial test a clamp leaves out the nodes it shares with the perpendicular
  clamps, which would otherwise be pulled two ways at once.

A grip's travel at t = 1 is Δ = (λ − 1) L_grip (L_grip the initial grip separation): the side +1
grip moves by Δ and the side −1 grip holds, or, for a centred specimen (a biaxial machine with four
actuators) and on an axis a symmetry plane cuts, each grip moves by ±Δ/2 about the centre.
Symmetry planes (Specimen.symmetry) prescribe the normal displacement zero on their nodes; with
roller grips they take the place of the 3-2-1 supports, and only the rigid modes they leave free
are pinned.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from vlab.geometry.specimen import Specimen
from vlab.loading.restraint import unrestrained_modes


@dataclass(frozen=True)
class GripLoading:
    """Prescribed DOFs, their values at t = 1 (mm), and each moving grip's DOFs by axis.

    ``path``: where the prescribed values are not t · û_p (a rotating grip: torsion), the full-length
    vector u_p(t) (mm) at load parameter t; ``u_hat`` is then du_p/dt at t = 0.
    ``liquid``: a liquid-filled chamber the load drives instead of the grips (the bulge test:
    vlab.fe.liquid.Liquid), or None."""

    prescribed: np.ndarray
    u_hat: np.ndarray  # full-length vector, nonzero only on prescribed DOFs
    moving_dofs: dict[int, np.ndarray]  # axis -> DOFs whose reaction the load cell sums
    path: Callable[[float], np.ndarray] | None = None
    liquid: object | None = None


def grip_loading(specimen: Specimen, X: np.ndarray, stretch: tuple[float, ...], kind: str) -> GripLoading:
    """Prescribed displacements for grip stretches ``stretch`` on axes 0, 1, … (one per entry;
    the test kind decides which: vlab.loading.kinds)."""
    dim = X.shape[1]  # 3, or 2 for a sheet; dof = dim * node + component
    u_hat = np.zeros(dim * len(X))
    fixed: set[int] = set()
    moving: dict[int, np.ndarray] = {}
    axes = dict(enumerate(stretch))
    clamped = kind == "clamped"
    for axis, target in axes.items():
        # a clamp leaves out the nodes it shares with the clamps of another loaded axis
        shared = [g.select(X) for g in specimen.grips if g.axis in axes and g.axis != axis] if clamped else []
        for grip in specimen.grips_on(axis):
            nodes = grip.select(X)
            if shared:
                nodes &= ~np.any(shared, axis=0)
            nodes = np.flatnonzero(nodes)
            for c in (range(dim) if clamped else (axis,)):
                fixed.update(dim * nodes + c)
            dofs = dim * nodes + axis
            u_hat[dofs] = _travel(specimen, axis, grip.side, target)
            if grip.side > 0:
                moving[axis] = dofs
    fixed.update(_symmetry_dofs(specimen, X))
    if not clamped:
        fixed.update(_rigid_body_supports(specimen, X, tuple(axes), sorted(fixed)))
    return GripLoading(np.array(sorted(fixed), dtype=np.int64), u_hat, moving)


def _travel(specimen: Specimen, axis: int, side: int, stretch: float) -> float:
    """A grip's displacement along its axis at t = 1 (mm), module docstring."""
    delta = (stretch - 1.0) * specimen.grip_separation[axis]
    if specimen.centred or specimen.reduced(axis):
        return side * delta / 2
    return delta if side > 0 else 0.0


def _symmetry_dofs(specimen: Specimen, X: np.ndarray) -> list[int]:
    """Normal-displacement DOFs of the nodes on the symmetry planes."""
    tol, dim = 1e-9 * specimen.length_scale, X.shape[1]
    return [int(d) for axis, value in specimen.symmetry
            for d in dim * np.flatnonzero(np.abs(X[:, axis] - value) <= tol) + axis]


def _rigid_body_supports(specimen: Specimen, X: np.ndarray, axes: tuple[int, ...], prescribed: list[int]) -> list[int]:
    """DOFs that pin the modes roller grips (and symmetry planes) leave free, at nodes that stay
    put homogeneously; a candidate is taken only if it restrains a mode still free, so the
    supports never over-constrain the body."""
    lo, hi = X.min(axis=0), X.max(axis=0)
    origin = int(np.argmin(np.linalg.norm(X - lo, axis=1)))
    if X.shape[1] == 2:  # sheet: the x edges hold x and the rotation; one node holds y
        return [] if 1 in axes else [2 * origin + 1]
    side = int(np.argmin(np.linalg.norm(X - np.array([lo[0], hi[1], lo[2]]), axis=1)))
    candidates = [3 * origin + 2] if 1 in axes else [3 * origin + 1, 3 * origin + 2, 3 * side + 2]
    if not specimen.symmetry:
        return candidates
    chosen: list[int] = []
    free = len(unrestrained_modes(X, np.array(prescribed)))
    for dof in candidates:
        left = len(unrestrained_modes(X, np.array(prescribed + chosen + [dof])))
        if left < free:
            chosen.append(dof)
            free = left
    return chosen
