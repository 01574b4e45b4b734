"""The stress in the centre of a cruciform from the finite-element field, beside the nominal stress.

A lab cannot measure the stress in a cruciform's gauge region: it knows the arm forces F_x, F_y and
quotes the nominal stress s = F / A_arm (A_arm = arm width × thickness; with a thinned centre,
arm width × gauge thickness). The FE field gives the
centre stress as the volume average of the first Piola stress over the central gauge region G,
    P̄_aa = ∫_G P_aa dV / ∫_G dV        (a = x, y; MPa, force per reference area like F/A),
and the correction factor k_a = P̄_aa / s_a, which a lab would take from such a calculation to turn
its nominal stress into the gauge-region stress. With it the probe reads the centre strains
ε̄_aa = ∫_G (√C_aa − 1) dV / ∫_G dV (a = x, y, z; engineering strain of a fibre along a), the state
the E and ν fit pairs with P̄ (measure/elastic_constants.py): averages over the same region, so a
linear law holds between them whatever the non-uniformity of the field inside G (P̄_zz, small but
not zero where the thickness changes, is read too).

k < 1: the section through the centre normal to x cuts the central square *and* the two y-arms,
and the fillets tie them together, so part of F_x bypasses the gauge region through the
neighbouring arms (the y-arms are stretched sideways); only the rest loads the central square
over its width. Slits cut the arms into fingers that cannot carry load across, so k rises
towards 1 with more and longer slits. The average is over whole elements whose centroid lies in G.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.space import DisplacementSpace
from vlab.geometry.specimen import Specimen


@dataclass
class CentreStressProbe:
    """Reads P̄_aa and ε̄_aa (a = x, y, z) over the elements of the specimen's "centre" region."""

    space: DisplacementSpace
    material: object
    elements: np.ndarray

    @classmethod
    def build(cls, space: DisplacementSpace, specimen: Specimen, material) -> "CentreStressProbe | None":
        if "centre" not in specimen.regions or material is None:
            return None
        mesh = space.basis.mesh
        centroids = mesh.p[:, mesh.t].mean(axis=1).T
        elements = np.flatnonzero(specimen.regions["centre"](centroids))
        return cls(space, material, elements) if len(elements) else None

    def read(self, F: np.ndarray) -> dict[str, float]:
        """Centre averages at a state with deformation gradient F (3, 3, e, q): ``stress_x``,
        ``stress_y``, ``stress_z`` (P̄_aa, MPa) and ``strain_x``, ``strain_y``, ``strain_z`` (ε̄_aa, 1)."""
        Fe = F[:, :, self.elements]
        P = self.material.stress(Fe)
        w = self.space.dx[self.elements]
        total = float(np.sum(w))
        out = {f"stress_{'xyz'[a]}": float(np.sum(P[a, a] * w) / total) for a in range(3)}
        for a in range(3):
            stretch = np.sqrt(np.einsum("ieq,ieq->eq", Fe[:, a], Fe[:, a]))
            out[f"strain_{'xyz'[a]}"] = float(np.sum((stretch - 1.0) * w) / total)
        return out


def centre_report(curve, window: tuple[float, float], method: str) -> dict | None:
    """Nominal and centre stress per axis with their correction factor k = P̄/s, at small strain
    (the last level whose centre strain is within the modulus window) and at the final level, and
    the E, ν a lab would report from the extensometers and the nominal stress (off by ~1/k)."""
    if not curve.centre or not curve.t:
        return None
    from vlab.measure.elastic_constants import nominal_biaxial

    lead = np.max(np.abs([curve.centre["strain_x"], curve.centre["strain_y"]]), axis=0)
    small = np.flatnonzero(lead <= window[1] * (1 + 1e-9))

    def at(i: int) -> dict:
        row = {"stretch": [curve.stretch[a][i] for a in curve.axes]}
        for a in curve.axes:
            xy = "xy"[a]
            nominal = curve.force[a][i] / curve.area0[a]
            centre = curve.centre[f"stress_{xy}"][i]
            row |= {f"nominal_stress_{xy}": nominal, f"centre_stress_{xy}": centre,
                    f"correction_factor_{xy}": centre / nominal if nominal != 0 else None}
        return row

    lab = nominal_biaxial(curve, window, method)
    return {"area0": {"xy"[a]: curve.area0[a] for a in curve.axes},
            "small_strain": at(int(small[-1])) if len(small) else None, "final": at(len(curve.t) - 1),
            "E_nominal": lab.E, "nu_nominal": lab.nu,
            "note": "centre stress = volume average of P over the gauge region (FE field); nominal = "
                    "load-cell force / (arm width x gauge-region thickness); correction factor = centre / nominal; "
                    "E_nominal, nu_nominal: from extensometers and nominal stress, as a lab without the "
                    "FE correction would report"}
