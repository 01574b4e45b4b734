"""Prescribed displacements of a confined-compression test in a frictionless rigid die,
u_p(t) = t · û_p (vlab.loading.kinds.confined).

The platens: the end face x = 0 holds u_x = 0, the end face x = L moves by (λ − 1) L along x; both
are free to slide across (frictionless). The die: the lateral surface may slide along it but not
leave or enter it.
- On a block the die's walls are the faces normal to y and z: u_y = 0 on y = 0, W and u_z = 0 on
  z = 0, H (the exact frictionless condition: nothing is held along the walls).
- On a cylinder the wall is r = a: the frictionless condition is u · e_r = 0 with u_x and the hoop
  displacement u_θ free. An isotropic cylinder compressed along its axis has u_θ ≡ 0 by symmetry,
  so the wall is prescribed as u_y = u_z = 0 on r = a, which is that condition on the path of the
  test (and fixes the rotation about x, which the die's friction would otherwise not).
Every rigid-body mode is held by these (no extra supports). The homogeneous solution is
F = diag(λ, 1, 1): the oracle (vlab.loading.kinds.confined).
"""

from __future__ import annotations

import numpy as np

from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading

__all__ = ["die_loading"]


def die_loading(specimen: Specimen, X: np.ndarray, stretch: float) -> GripLoading:
    """Platens along x and the die's walls (module docstring)."""
    fixed, moving = specimen.grips_on(0)
    low, high = np.flatnonzero(fixed.select(X)), np.flatnonzero(moving.select(X))
    u_hat = np.zeros(3 * len(X))
    u_hat[3 * high] = (stretch - 1.0) * specimen.grip_separation[0]
    dofs = [3 * low, 3 * high]
    if "lateral" in specimen.regions:  # a cylinder: the wall r = a
        wall = np.flatnonzero(specimen.regions["lateral"](X))
        dofs += [3 * wall + 1, 3 * wall + 2]
    else:  # a block: the faces normal to y and z
        tol = 1e-9 * specimen.length_scale
        lo, hi = X.min(axis=0), X.max(axis=0)
        for c in (1, 2):
            wall = np.flatnonzero((np.abs(X[:, c] - lo[c]) <= tol) | (np.abs(X[:, c] - hi[c]) <= tol))
            dofs.append(3 * wall + c)
    return GripLoading(np.unique(np.concatenate(dofs)).astype(np.int64), u_hat, {0: 3 * high})
