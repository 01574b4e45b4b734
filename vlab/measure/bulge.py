"""What a bulge test measures (vlab.loading.bulge on a clamped membrane quarter), and the lab's
pole-stress estimate.

Readings per level (a = the rim radius, t₀ the sheet's thickness, V₀ the quarter chamber's liquid
volume; f the reactions, N):
- ``pressure`` p (MPa): the liquid's, K_f (V_p(t) − V) / V₀ under volume control, t p* under
  pressure control (vlab.fe.liquid);
- ``volume_ratio`` (V₀ + V) / V₀, V the volume the wetted face encloses with its initial plane
  (mm³, the facetted quarter's; vlab.fe.liquid.enclosed_volume);
- ``pole_height`` h (mm): the mean u_z of the pole's nodes through the thickness (the mid-surface);
- ``pole_stretch`` λ: the in-plane stretch at the pole, ((C_xx + C_yy) / 2)^½ averaged over the
  cells that touch the pole axis (dx-weighted; equibiaxial there by symmetry, to O(h²));
- ``pole_stress_fe`` (MPa): the FE's membrane stress at the pole, (σ_xx + σ_yy)/2 − σ_zz (Cauchy,
  the card at the same cells' F, averaged likewise): the difference drops the hydrostatic part a
  single layer of near-incompressible cells resolves worst, and it is the membrane stress of a
  sheet whose σ_zz is the liquid's −p on one face and 0 on the other;
- ``pole_stress`` (MPa): the lab's estimate from what a bulge rig reads (p, h), a spherical cap
  through the rim: σ = p R_c / (2 t), R_c = (a² + h²) / (2 h), t = t₀ / λ² (incompressible);
- the rim's z reaction (the load cell, N): −p times the quarter's projected area, by equilibrium.
Oracle (kind.reference): at the pole the state is equibiaxial, σ_eq(λ) = λ Ŵ'(λ) / 2 with
Ŵ(λ) = ψ(diag(λ, λ, λ⁻²)) (vlab.loading.thick_sphere.equibiaxial_stress).
"""

from __future__ import annotations

import numpy as np

from vlab.fe.liquid import enclosed_volume

__all__ = ["bulge_readers", "lab_pole_stress"]


def lab_pole_stress(p, h, radius: float, thickness: float, stretch):
    """σ = p R_c / (2 t₀ / λ²), R_c = (a² + h²) / (2 h) (MPa; arrays element-wise; module docstring)."""
    p, h, lam = np.asarray(p, float), np.asarray(h, float), np.asarray(stretch, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(h > 0, p * (radius**2 + h * h) / (2.0 * h) / (2.0 * thickness / lam**2), 0.0)


def _membrane_stress(material, F: np.ndarray, w: np.ndarray) -> float:
    """The FE's pole stress (MPa): (σ₁₁ + σ₂₂)/2 − σ₃₃ with σ = P Fᵀ / J, averaged over the pole's
    quadrature points with weights ``w``: the difference is free of the hydrostatic part, and equals
    the in-plane stress of the equibiaxial membrane state (σ₃₃ = 0) it is compared with."""
    P = material.stress(F)
    sigma = np.einsum("ij...,kj...->ik...", P, F) / np.linalg.det(np.moveaxis(F, (0, 1), (-2, -1)))
    membrane = (sigma[0, 0] + sigma[1, 1]) / 2.0 - sigma[2, 2]
    return float(np.sum(membrane * w) / np.sum(w))


def bulge_readers(space, specimen, loading, material) -> dict:
    """Readers of the module docstring (``material`` None: no FE pole stress)."""
    liquid = loading.liquid
    X = space.node_coordinates
    wetted = np.unique(liquid.triangles)
    local = np.searchsorted(wetted, liquid.triangles)
    V0, a = specimen.area0[0], specimen.grip_separation[0]
    thickness = float(np.ptp(X[:, 2]))
    pole = np.flatnonzero(specimen.regions["pole"](X))
    cells = np.flatnonzero(np.any(np.isin(space.element_nodes, pole), axis=1))
    w = space.dx[cells]
    cache: dict = {}

    def state(level) -> dict:
        if cache.get("level") is not level:
            u = level.evaluation.u
            x = X[wetted] + u[(3 * wetted[:, None] + np.arange(3))].reshape(-1, 3)
            volume = enclosed_volume(x, local)
            F = level.evaluation.F[:, :, cells]
            C = np.einsum("ki...,kj...->ij...", F, F)
            lam = float(np.sum(np.sqrt((C[0, 0] + C[1, 1]) / 2.0) * w) / np.sum(w))
            out = {"volume": volume, "pressure": liquid.pressure(level.t, volume), "stretch": lam,
                   "height": float(np.mean(u[3 * pole + 2]))}
            if material is not None:
                out["stress_fe"] = _membrane_stress(material, F, w)
            cache["level"], cache["state"] = level, out
        return cache["state"]

    def lab(level) -> float:
        s = state(level)
        return float(lab_pole_stress(s["pressure"], s["height"], a, thickness, s["stretch"]))

    readers = {"pressure": lambda level: state(level)["pressure"],
               "volume_ratio": lambda level: (V0 + state(level)["volume"]) / V0,
               "pole_height": lambda level: state(level)["height"],
               "pole_stretch": lambda level: state(level)["stretch"],
               "pole_stress": lab}
    if material is not None:
        readers["pole_stress_fe"] = lambda level: state(level)["stress_fe"]
    return readers
