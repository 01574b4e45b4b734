"""Prescribed displacements and the liquid of the bulge test on a clamped membrane quarter
(vlab.loading.kinds.inflation, vlab.geometry.membrane).

The rim r = a is clamped (u = 0 through the thickness); the symmetry planes hold the normal
displacement (u_x = 0 on x = 0, u_y = 0 on y = 0). No grip moves: the load is the liquid under the
face z = 0 (vlab.fe.liquid), either

- ``control = "volume"``: a syringe pumps V_p(t) = t (v − 1) V₀ into the chamber (V₀ the quarter
  chamber's liquid volume, vlab.geometry.membrane.chamber_volume; v the scene's final
  ``volume_ratio`` (V₀ + V) / V₀); the liquid is water, K_f = 2200 MPa, so the enclosed volume V
  lags V_p by p V₀ / K_f (5e-5 of V at p = 0.05 MPa and V = V₀ / 2 on a = 10 mm);
- ``control = "pressure"``: p(t) = t p* (MPa).

The load cell is the rim: its reactions balance the liquid's force on the sheet.
"""

from __future__ import annotations

import numpy as np

from vlab.loading.liquid import Liquid
from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading

__all__ = ["LIQUID_BULK_MODULUS", "bulge_loading", "cap_area_ratio", "face_triangles", "wetted_triangles"]

LIQUID_BULK_MODULUS = 2200.0  # MPa, water at 20 °C


def cap_area_ratio(volume_ratio: float) -> float:
    """A = 1 + η², the area of the spherical cap that encloses the bulge of ``volume_ratio`` v over
    the flat disc's area π a² (η = h/a, the cap's height over the rim's radius).

    The bulge holds V = (v − 1) π a³ (the chamber V₀ = π a³); a cap of height h holds
    π h (3a² + h²)/6, so η³ + 3η = 6 (v − 1), whose one real root is (Cardano, q = 3 (v − 1))
    η = ∛(q + √(q² + 1)) + ∛(q − √(q² + 1)); a cap has the area π (a² + h²). Of every surface
    spanning the rim and enclosing V the cap has the least area, so some point of an incompressible
    sheet reaches the area stretch λ₁ λ₂ ≥ A, and Ī₁ = λ₁² + λ₂² + (λ₁ λ₂)⁻² ≥ 2A + A⁻² there (for
    A ≥ 1): the equibiaxial stretch √A is a lower bound of the bulge's worst state."""
    q = 3.0 * (volume_ratio - 1.0)
    root = np.sqrt(q * q + 1.0)
    eta = np.cbrt(q + root) + np.cbrt(q - root)
    return float(1.0 + eta * eta)


def face_triangles(mesh, on_face, normal) -> np.ndarray:
    """The boundary facets whose nodes all satisfy ``on_face`` (positions (k, 3) -> bool (k,)), each
    split into two triangles counter-clockwise about ``normal(centroid)`` (the side the liquid
    pushes towards): (n, 3) node indices."""
    facets = mesh.facets[:, mesh.boundary_facets()]
    points = mesh.p.T
    triangles = []
    for quad in facets.T:
        P = points[quad]
        if not np.all(on_face(P)):
            continue
        c = P.mean(axis=0)
        n = normal(c)
        e1 = P[0] - c
        e2 = np.cross(n, e1)
        quad = quad[np.argsort(np.arctan2((P - c) @ e2, (P - c) @ e1))]
        triangles += [quad[[0, 1, 2]], quad[[0, 2, 3]]]
    return np.array(triangles, dtype=np.int64)


def wetted_triangles(mesh, tol: float) -> np.ndarray:
    """The membrane's face z = 0, counter-clockwise seen from +z."""
    return face_triangles(mesh, lambda P: np.abs(P[:, 2]) <= tol, lambda c: np.array([0.0, 0.0, 1.0]))


def bulge_loading(specimen: Specimen, X: np.ndarray, control: str, target: float) -> GripLoading:
    """The clamped rim, the symmetry planes and the liquid (module docstring); ``target`` is the
    final volume ratio (control "volume") or pressure (MPa, control "pressure")."""
    tol = 1e-9 * specimen.length_scale
    rim = np.flatnonzero(specimen.regions["rim"](X))
    dofs = [3 * rim + c for c in range(3)]
    dofs += [3 * np.flatnonzero(np.abs(X[:, c]) <= tol) + c for c in (0, 1)]
    V0 = specimen.area0[0]
    triangles = wetted_triangles(specimen.mesh, tol)
    if control == "volume":
        liquid = Liquid(triangles, "volume", (target - 1.0) * V0, LIQUID_BULK_MODULUS / V0)
    else:
        liquid = Liquid(triangles, "pressure", target)
    return GripLoading(np.unique(np.concatenate(dofs)).astype(np.int64), np.zeros(3 * len(X)), {0: 3 * rim + 2},
                       liquid=liquid)
