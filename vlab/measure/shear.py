"""What a simple-shear test measures (vlab.loading.kinds.simple_shear).

- G: the slope of the nominal shear stress τ = F_s / A₀ against the gauge-mark shear strain γ_g
  over the modulus window (|γ_g| in it), with R² and the slope's standard error (measure/fit.py);
  G_plate the same against the plate-travel shear γ = Δx / H (it includes the edge effects).
- At the largest |γ| reached: the nominal normal stress σ_n = F_n / A₀ on the plate and, from the
  FE field, the normal-stress difference N₁ = σ̄₁₁ − σ̄₂₂ of the Cauchy stress σ = P Fᵀ / J averaged
  over the centre region (the whole block on the kinematic set-up, where N₁ = μ γ² for
  Neo-Hookean), which a lab gets only from a cone-and-plate or a normal-force analysis.
- The field probe (results.json → homogeneity): over the centre region, the spread of the local
  shear F₁₂ and of P₁₂, the centre shear stress over the nominal one (the edge-effect factor, 1 on
  the kinematic block), and the distance from simple shear d = mean ‖F − (I + γ̄ e₁⊗e₂)‖ / |γ̄|
  (γ̄ the mean F₁₂; 0 for the homogeneous state).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.space import DisplacementSpace
from vlab.geometry.specimen import Specimen
from vlab.measure.elastic_constants import ElasticConstants
from vlab.measure.fit import FitError, fit_line
from vlab.measure.homogeneity import _summary

__all__ = ["shear_constants", "centre_cauchy_readers", "ShearFieldProbe", "CENTRE_REGION"]

CENTRE_REGION = "core"  # the specimen region the centre averages read (all elements if absent)


def _core(space: DisplacementSpace, specimen: Specimen) -> np.ndarray:
    mesh = space.basis.mesh
    if CENTRE_REGION not in specimen.regions:
        return np.arange(mesh.t.shape[1])
    centroids = mesh.p[:, mesh.t].mean(axis=1).T
    return np.flatnonzero(specimen.regions[CENTRE_REGION](centroids))


def _cauchy(material, F: np.ndarray) -> np.ndarray:
    P = material.stress(F)
    J = np.linalg.det(np.moveaxis(F, (0, 1), (-2, -1)))
    return np.einsum("ij...,kj...->ik...", P, F) / J


def centre_cauchy_readers(space: DisplacementSpace, specimen: Specimen, material) -> dict:
    """Readers of σ̄_xx, σ̄_yy, σ̄_zz, σ̄_xy (MPa) over the centre region, or {} without a material."""
    if material is None:
        return {}
    elements = _core(space, specimen)
    w = space.dx[elements]
    cache: dict = {}

    def component(i: int, j: int):
        def read(level) -> float:
            if cache.get("level") is not level:
                cache["level"], cache["sigma"] = level, _cauchy(material, level.evaluation.F[:, :, elements])
            return float(np.sum(cache["sigma"][i, j] * w) / np.sum(w))
        return read

    return {f"centre_cauchy_{name}": component(i, j)
            for name, (i, j) in {"xx": (0, 0), "yy": (1, 1), "zz": (2, 2), "xy": (0, 1)}.items()}


def shear_constants(curve, window, method) -> ElasticConstants:
    """G (gauge marks and plate travel) and the normal stresses at the largest |γ| (module docstring)."""
    tau = curve.column("stress", 0)
    extra: dict = {}
    note = "simple shear: E and nu are not measured; G = slope of shear stress against gauge-mark shear"
    try:
        g_fit = fit_line(np.array(curve.strain[0]), tau, window, method)
        extra |= {"G": g_fit.slope, "G_fit": g_fit.as_dict()}
        plate = fit_line(np.array(curve.stretch[0]), tau, window, method)
        extra |= {"G_plate": plate.slope, "G_plate_fit": plate.as_dict()}
    except FitError as exc:
        note = f"G not measured: {exc}"
        extra |= {"G": None, "G_fit": None, "G_plate": None, "G_plate_fit": None}
    extra |= _at_peak(curve)
    return ElasticConstants(None, None, None, None, [{"axis": "xy", "G": extra.get("G")}], note, extra)


def _at_peak(curve) -> dict:
    """Normal stress and N₁ at the row of largest |γ| (plate travel)."""
    if not curve.t:
        return {}
    i = int(np.argmax(np.abs(curve.stretch[0])))
    out = {"shear_at_peak": curve.stretch[0][i],
           "normal_stress_at_peak": (curve.extra["normal_force"][i] / curve.area0[0]
                                     if curve.extra.get("normal_force") else None)}
    if "centre_cauchy_xx" in curve.extra:
        out["normal_stress_difference"] = curve.extra["centre_cauchy_xx"][i] - curve.extra["centre_cauchy_yy"][i]
        out["normal_stress_difference_note"] = "N1 = sigma_xx - sigma_yy, Cauchy, FE centre average, at the largest |shear|"
    return out


@dataclass
class ShearFieldProbe:
    """How far the centre region is from simple shear (module docstring)."""

    space: DisplacementSpace
    material: object
    elements: np.ndarray
    area0: float

    @classmethod
    def build(cls, space: DisplacementSpace, specimen: Specimen, material) -> "ShearFieldProbe | None":
        if material is None:
            return None
        return cls(space, material, _core(space, specimen), specimen.area0[1])

    def read(self, F: np.ndarray, force: float) -> dict:
        """Statistics of a state F (3, 3, e, q) with plate force ``force`` (N). Each element's
        shear is read in its own sense s_e = sign(mean F₁₂ of the element) times the test's sense
        sign(force), so the two layers of a double lap, sheared in opposite senses, count alike."""
        Fe = F[:, :, self.elements]
        w = self.space.dx[self.elements]
        test_sense = 1.0 if force >= 0 else -1.0
        sense = np.sign(np.sum(Fe[0, 1] * w, axis=1, keepdims=True))
        sense[sense == 0] = 1.0
        shear = test_sense * sense * Fe[0, 1]
        P12 = test_sense * sense * self.material.stress(Fe)[0, 1]
        gamma = float(np.sum(shear * w) / np.sum(w))
        ideal = np.zeros_like(Fe)
        ideal[0, 0] = ideal[1, 1] = ideal[2, 2] = 1.0
        ideal[0, 1] = test_sense * sense * gamma
        distance = float(np.sum(np.linalg.norm((Fe - ideal).reshape(9, *w.shape), axis=0) * w) / np.sum(w))
        nominal = force / self.area0
        centre = float(np.sum(P12 * w) / np.sum(w))
        return {"shear_strain": _summary(shear, w), "shear_stress": _summary(P12, w),
                "nominal_shear_stress": nominal,
                "centre_over_nominal": centre / nominal if nominal else None,
                "distance_from_simple_shear": distance / abs(gamma) if gamma else None,
                "centre_elements": int(len(self.elements))}
