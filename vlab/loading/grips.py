"""Grips turn a test into prescribed displacements u_p(t) = t · û_p on named regions.

- roller (frictionless) grips prescribe only the displacement along the pulling axis, so the
  faces under the grips may slide and contract freely; the remaining rigid-body modes are removed
  at single nodes (3-2-1 rule; on a 2D sheet one node's y in uniaxial tests) at points the
  homogeneous solution leaves in place.
- clamped grips prescribe all components (three, or two on a 2D sheet): the fixed grip holds, the moving grip translates
  along its axis. In a biaxial test a clamp leaves out the nodes it shares with the perpendicular
  clamps, which would otherwise be pulled two ways at once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.geometry.specimen import Specimen


@dataclass(frozen=True)
class GripLoading:
    """Prescribed DOFs, their values at t = 1 (mm), and each moving grip's DOFs by axis."""

    prescribed: np.ndarray
    u_hat: np.ndarray  # full-length vector, nonzero only on prescribed DOFs
    moving_dofs: dict[int, np.ndarray]  # axis -> DOFs whose reaction the load cell sums


def grip_loading(specimen: Specimen, X: np.ndarray, stretch: tuple[float, ...], kind: str) -> GripLoading:
    """Prescribed displacements for grip stretches ``stretch`` on axes 0 (and 1 if biaxial)."""
    dim = X.shape[1]  # 3, or 2 for a sheet; dof = dim * node + component
    n_dofs = dim * len(X)
    u_hat = np.zeros(n_dofs)
    fixed: set[int] = set()
    moving: dict[int, np.ndarray] = {}
    axes = range(len(stretch))
    clamped = kind == "clamped"
    others = [g.select(X) for g in specimen.grips if g.axis in axes]
    for axis in axes:
        for grip in specimen.grips_on(axis):
            nodes = grip.select(X)
            if clamped and len(stretch) > 1:
                nodes &= ~np.any([m for g, m in zip(specimen.grips, others) if g.axis != axis], axis=0)
            nodes = np.flatnonzero(nodes)
            comps = range(dim) if clamped else (axis,)
            for c in comps:
                fixed.update(dim * nodes + c)
            if grip.side > 0:
                dofs = dim * nodes + axis
                u_hat[dofs] = (stretch[axis] - 1.0) * specimen.grip_separation[axis]
                moving[axis] = dofs
    if not clamped:
        fixed.update(_rigid_body_supports(specimen, X, len(stretch)))
    prescribed = np.array(sorted(fixed), dtype=np.int64)
    return GripLoading(prescribed, u_hat, moving)


def _rigid_body_supports(specimen: Specimen, X: np.ndarray, n_axes: int) -> list[int]:
    """DOFs that pin the modes roller grips leave free, at nodes that stay put homogeneously."""
    lo, hi = X.min(axis=0), X.max(axis=0)
    origin = int(np.argmin(np.linalg.norm(X - lo, axis=1)))
    if X.shape[1] == 2:  # sheet: the x edges hold x and the rotation; one node holds y
        return [] if n_axes == 2 else [2 * origin + 1]
    if n_axes == 2:
        return [3 * origin + 2]
    side = int(np.argmin(np.linalg.norm(X - np.array([lo[0], hi[1], lo[2]]), axis=1)))
    return [3 * origin + 1, 3 * origin + 2, 3 * side + 2]
