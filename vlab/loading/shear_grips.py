"""Prescribed displacements of a simple-shear test, u_p(t) = t · û_p (vlab.loading.kinds.simple_shear).

- kinematic: every boundary node of a block follows x = X + γ (Y − Y₀) e₁ (all components
  prescribed), so the only solution is the homogeneous F = I + γ e₁⊗e₂; the face Y = Y_max is the
  moving plate whose reactions the load cells read. On a structured mesh its x and y reactions are
  exactly P₁₂ A and P₂₂ A: the shares of the side faces x = 0 and x = L in the top row of nodes
  cancel (equal and opposite tractions ±P e₁ on matching face meshes) and the faces z = 0, D carry
  P₁₃ = P₂₃ = 0.
- plates: the grip ``y-`` (a rigid plate) holds every component; the grip ``y+`` moves by γ H along
  x with u_y = u_z = 0 (normal gap held), H the initial gap. The other faces are free.
"""

from __future__ import annotations

import numpy as np

from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading

__all__ = ["kinematic_shear", "plate_shear"]


def _dofs(nodes: np.ndarray, comps) -> np.ndarray:
    return np.sort(np.concatenate([3 * nodes + c for c in comps]))


def kinematic_shear(specimen: Specimen, X: np.ndarray, gamma: float) -> GripLoading:
    """The whole boundary of the block on x = X + γ (Y − Y₀) e₁ at t = 1 (module docstring)."""
    tol = 1e-9 * specimen.length_scale
    lo, hi = X.min(axis=0), X.max(axis=0)
    boundary = np.flatnonzero(np.any((np.abs(X - lo) <= tol) | (np.abs(X - hi) <= tol), axis=1))
    top = np.flatnonzero(np.abs(X[:, 1] - hi[1]) <= tol)
    u_hat = np.zeros(3 * len(X))
    u_hat[3 * boundary] = gamma * (X[boundary, 1] - lo[1])
    return GripLoading(_dofs(boundary, range(3)), u_hat, {0: 3 * top, 1: 3 * top + 1})


def plate_shear(specimen: Specimen, X: np.ndarray, gamma: float) -> GripLoading:
    """Rigid plates on the grips y− (held) and y+ (moved by γ H along x, gap held)."""
    fixed = np.flatnonzero(next(g for g in specimen.grips if g.axis == 1 and g.side < 0).select(X))
    moving = np.flatnonzero(next(g for g in specimen.grips if g.axis == 1 and g.side > 0).select(X))
    u_hat = np.zeros(3 * len(X))
    u_hat[3 * moving] = gamma * specimen.grip_separation[1]
    prescribed = np.union1d(_dofs(fixed, range(3)), _dofs(moving, range(3)))
    return GripLoading(prescribed, u_hat, {0: 3 * moving, 1: 3 * moving + 1})
