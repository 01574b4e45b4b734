"""How uniform the gauge section is, and how much the fillets concentrate stress.

Read at the quadrature points of a converged state (the lab's equivalent is a strain field from
digital image correlation):
- axial strain   ε = √C₁₁ − 1, the engineering strain of a fibre along the loading axis x;
- axial stress   P₁₁, the nominal (first Piola) stress, force per reference area like F/A₀.
Over the gauge region (elements whose centroid lies between the gauge marks) each is summarised by
its volume-weighted mean, min, max, spread = (max − min)/|mean| and coefficient of variation
std/|mean|. The stress concentration factor is K = max P₁₁ over the fillet region / (F/A₀).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.space import DisplacementSpace
from vlab.geometry.specimen import Specimen


def _summary(values: np.ndarray, weights: np.ndarray) -> dict:
    mean = float(np.sum(values * weights) / np.sum(weights))
    std = float(np.sqrt(np.sum((values - mean) ** 2 * weights) / np.sum(weights)))
    scale = max(abs(mean), 1e-300)
    return {"mean": mean, "min": float(values.min()), "max": float(values.max()),
            "spread": float(values.max() - values.min()) / scale, "cv": std / scale}


@dataclass
class HomogeneityProbe:
    """Evaluates the gauge-section statistics of a state on a fixed set of elements."""

    space: DisplacementSpace
    material: object
    gauge: np.ndarray  # element indices
    fillets: np.ndarray  # element indices (may be empty)
    area0: float

    @classmethod
    def build(cls, space: DisplacementSpace, specimen: Specimen, material) -> "HomogeneityProbe | None":
        if "gauge" not in specimen.regions:
            return None
        mesh = space.basis.mesh
        centroids = mesh.p[:, mesh.t].mean(axis=1).T  # (n_elements, 3)
        gauge = np.flatnonzero(specimen.regions["gauge"](centroids))
        fillets = (np.flatnonzero(specimen.regions["fillets"](centroids))
                   if "fillets" in specimen.regions else np.array([], dtype=int))
        return cls(space, material, gauge, fillets, specimen.area0[0])

    def axial(self, F: np.ndarray, elements: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(axial strain, P₁₁) at the quadrature points of ``elements``, each (n, q)."""
        Fe = F[:, :, elements]
        C11 = np.einsum("ieq,ieq->eq", Fe[:, 0], Fe[:, 0])
        return np.sqrt(C11) - 1.0, self.material.stress(Fe)[0, 0]

    def read(self, F: np.ndarray, force: float) -> dict:
        """Statistics at a state with deformation gradient F (3,3,e,q) and load-cell force (N)."""
        strain, stress = self.axial(F, self.gauge)
        w = self.space.dx[self.gauge]
        nominal = force / self.area0
        out = {"axial_strain": _summary(strain, w), "axial_stress": _summary(stress, w),
               "nominal_stress": nominal, "gauge_elements": int(len(self.gauge))}
        if len(self.fillets):
            peak = float(self.axial(F, self.fillets)[1].max())
            out["fillet_max_stress"] = peak
            out["stress_concentration"] = peak / nominal if nominal != 0 else None
        return out
