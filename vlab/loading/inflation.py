"""Prescribed displacements of the inflation of a sphere-shell octant under volume control,
u_p(t) = t · û_p (vlab.loading.kinds.inflation).

The cavity's volume is prescribed through its wall: every node of the inner surface r = A moves
radially to r = λ_a(t) A, u = (λ_a(t) − 1) X, so the facetted cavity scales by λ_a and its volume
is V(t) = λ_a(t)³ V₀ exactly. This is volume control on the spherically symmetric path (the path
the closed form describes); it holds the inner surface spherical, so it cannot follow an
aspherical bifurcation, which the symmetric octant could not show either. The symmetry planes hold
the normal displacement (u_x = 0 on x = 0, u_y = 0 on y = 0, u_z = 0 on z = 0); with the inner
surface driven, no rigid mode is left. The pressure is the reaction's work-conjugate,
p = Σ f_i · X_i / (dV/dλ_a) over the inner nodes (measure/inflation.py).

Under ``control = "pressure"`` (``pressure_loading``) the wall is free: a gas at p(t) = t p* fills
the cavity (vlab.fe.liquid, its "pressure" control on the inner surface's triangles; the prism
volume under them down to z = 0 is the octant's cavity, since their edges lie on the three
symmetry planes), and the symmetry planes alone are held.
"""

from __future__ import annotations

import numpy as np

from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading

__all__ = ["inflation_loading", "pressure_loading"]


def inflation_loading(specimen: Specimen, X: np.ndarray, stretch: float) -> GripLoading:
    """The driven cavity wall and the three symmetry planes (module docstring)."""
    inner = np.flatnonzero(specimen.regions["inner"](X))
    tol = 1e-9 * specimen.length_scale
    u_hat = np.zeros(3 * len(X))
    dofs = [3 * inner + c for c in range(3)]
    for c in range(3):
        u_hat[3 * inner + c] = (stretch - 1.0) * X[inner, c]
    dofs += _symmetry_dofs(X, tol)
    return GripLoading(np.unique(np.concatenate(dofs)).astype(np.int64), u_hat, {0: 3 * inner})


def _symmetry_dofs(X: np.ndarray, tol: float) -> list[np.ndarray]:
    return [3 * np.flatnonzero(np.abs(X[:, c]) <= tol) + c for c in range(3)]


def pressure_loading(specimen: Specimen, X: np.ndarray, pressure: float) -> GripLoading:
    """The symmetry planes and a pressure p(t) = t ``pressure`` (MPa) in the cavity (module docstring)."""
    from vlab.loading.liquid import Liquid
    from vlab.loading.bulge import face_triangles

    A = specimen.grip_separation[0]
    inner = np.flatnonzero(specimen.regions["inner"](X))
    triangles = face_triangles(specimen.mesh, lambda P: np.abs(np.linalg.norm(P, axis=1) - A) <= 1e-9 * A,
                               lambda c: c / np.linalg.norm(c))
    prescribed = np.unique(np.concatenate(_symmetry_dofs(X, 1e-9 * specimen.length_scale)))
    return GripLoading(prescribed.astype(np.int64), np.zeros(3 * len(X)), {0: 3 * inner},
                       liquid=Liquid(triangles, "pressure", pressure))
