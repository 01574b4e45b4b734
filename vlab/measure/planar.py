"""What a planar-tension (pure-shear) test measures (vlab.loading.kinds.planar).

- The planar modulus E_p = E/(1 − ν²): slope of the nominal stress F/A₀ against the extensometer
  strain over the modulus window; ν from the thickness strain, ε_z = −ν/(1 − ν) ε_x ⇒ ν = r/(1 + r),
  r = −dε_z/dε_x (Hooke with ε_y = 0, σ_z = 0: σ_y = ν σ_x, ε_x = (1 − ν²) σ_x / E); E = (1 − ν²) E_p.
  Incompressible: r = 1, ν = ½, E_p = 4μ = 4E/3. The width is held (ε_y = 0), so no lateral
  extensometer gives ν here. An isotropic solid has −1 < ν ≤ ½, i.e. −½ < r ≤ 1: a ratio outside
  that range by more than twice its fit's standard error (r = 1.064 ± 0.0004 on a locked
  displacement-only strip) says the gauge centre is not in homogeneous pure shear, and ν (and
  the E built on it) are then not reported ("not measured", with r); the planar modulus is.
- The field probe (results.json → homogeneity) over the specimen's gauge region (the centre of a
  planar-tension strip, away from its free edges): the axial strain √C₁₁ − 1, the lateral strain
  √C₂₂ − 1 (0 in pure shear) and P₁₁; the pure-shear stress P₁₁^ps of the material at the mean
  axial stretch (materials.homogeneous.planar); the distance from pure shear
  d = max |ε_yy| / |mean ε_xx|, and the ratio of the nominal stress to P₁₁^ps (what the lab's
  F/A₀ is worth as a pure-shear stress).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.space import DisplacementSpace
from vlab.geometry.specimen import Specimen
from vlab.materials.homogeneous import InadmissibleState, planar
from vlab.measure.elastic_constants import ElasticConstants
from vlab.measure.fit import FitError, fit_line
from vlab.measure.homogeneity import _summary

__all__ = ["planar_constants", "PureShearProbe"]


def planar_constants(curve, window, method) -> ElasticConstants:
    eps = np.array(curve.strain[0])
    try:
        p_fit = fit_line(eps, curve.column("stress", 0), window, method)
        r_fit = fit_line(eps, np.array(curve.thickness_strain), window, method)
    except FitError as exc:
        return ElasticConstants(None, None, None, None, [], f"not measured: {exc}",
                                {"planar_modulus": None, "planar_modulus_fit": None})
    r = -r_fit.slope
    extra = {"planar_modulus": p_fit.slope, "planar_modulus_fit": p_fit.as_dict(), "thickness_strain_ratio": r}
    margin = 2.0 * r_fit.slope_stderr  # noise may carry an incompressible solid's r a little past 1
    if not (R_RANGE[0] < r + margin and r - margin <= R_RANGE[1]):
        return ElasticConstants(None, None, None, r_fit.as_dict(), [{"axis": "x", "planar_modulus": p_fit.slope}],
                                _outside_note(r, r_fit.slope_stderr), extra)
    nu = r / (1.0 + r)
    E = (1.0 - nu**2) * p_fit.slope
    return ElasticConstants(E, nu, None, r_fit.as_dict(),
                            [{"axis": "x", "planar_modulus": p_fit.slope, "E": E, "nu": nu}],
                            "planar tension: E = (1 - nu^2) x planar modulus, nu from the thickness strain",
                            extra)


R_RANGE = (-0.5, 1.0)  # r = -dε_z/dε_x of an isotropic solid in pure shear: ν = r/(1 + r) in (−1, ½]


def _outside_note(r: float, stderr: float) -> str:
    return (f"not measured: the thickness strain ratio r = -d(eps_z)/d(eps_x) = {r:.4g} (+/- {stderr:.2g}) "
            f"is outside {R_RANGE[0]:g} < r <= {R_RANGE[1]:g}, so nu = r/(1 + r) = {r / (1.0 + r):.4g} is no "
            f"isotropic material's Poisson's ratio (-1 < nu <= 0.5): the gauge centre is not in homogeneous "
            f"pure shear (volumetric locking, or the clamps restraining the thickness); the planar modulus "
            f"is still reported")


@dataclass
class PureShearProbe:
    """The distance of a planar-tension specimen's gauge region from pure shear (module docstring)."""

    space: DisplacementSpace
    material: object
    gauge: np.ndarray
    area0: float

    @classmethod
    def build(cls, space: DisplacementSpace, specimen: Specimen, material) -> "PureShearProbe | None":
        if material is None or "gauge" not in specimen.regions:
            return None
        mesh = space.basis.mesh
        centroids = mesh.p[:, mesh.t].mean(axis=1).T
        return cls(space, material, np.flatnonzero(specimen.regions["gauge"](centroids)), specimen.area0[0])

    def read(self, F: np.ndarray, force: float) -> dict:
        Fe = F[:, :, self.gauge]
        w = self.space.dx[self.gauge]
        axial = np.sqrt(np.einsum("ieq,ieq->eq", Fe[:, 0], Fe[:, 0])) - 1.0
        lateral = np.sqrt(np.einsum("ieq,ieq->eq", Fe[:, 1], Fe[:, 1])) - 1.0
        P11 = self.material.stress(Fe)[0, 0]
        mean_axial = float(np.sum(axial * w) / np.sum(w))
        nominal = force / self.area0
        out = {"axial_strain": _summary(axial, w), "lateral_strain": _summary(lateral, w),
               "axial_stress": _summary(P11, w), "nominal_stress": nominal,
               "gauge_elements": int(len(self.gauge)),
               "distance_from_pure_shear": float(np.max(np.abs(lateral))) / max(abs(mean_axial), 1e-300)}
        try:
            ps = float(planar(self.material, 1.0 + mean_axial).P[0, 0])
            out |= {"pure_shear_stress": ps, "nominal_over_pure_shear": nominal / ps if ps else None}
        except InadmissibleState:
            out["pure_shear_stress"] = None
        return out
