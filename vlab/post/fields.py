"""Post-processing fields of a converged state, per cell, for renders and VTU files.

At every quadrature point (F and P from the body's material):
    J       = det F                                      volume ratio, 1
    σ       = P Fᵀ / J                                   Cauchy stress, MPa
    λ_max   = √(largest eigenvalue of C = Fᵀ F)          maximum principal stretch, 1
Cell values are the volume averages Σ_q v dx / Σ_q dx over the reference quadrature weights; the
von Mises stress σ_vm = √(3/2 s:s), s = σ − (tr σ / 3) I (MPa), is taken of the cell-averaged σ.
A body that has no stress at quadrature points (the spring network) provides its own cell Cauchy
stress through ``cell_cauchy(evaluation)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.fe.cell_fields import cauchy, cell_average

#: field name -> (label for scalar bars, unit)
FIELDS: dict[str, tuple[str, str]] = {
    "von-mises": ("von Mises Cauchy stress", "MPa"),
    "max-stretch": ("max principal stretch", "1"),
    "J": ("volume ratio J", "1"),
}


@dataclass(frozen=True)
class CellFields:
    """Per-cell post-processing values of one state, each array of shape (n_cells,)."""

    von_mises: np.ndarray
    max_stretch: np.ndarray
    J: np.ndarray

    def get(self, name: str) -> np.ndarray:
        return {"von-mises": self.von_mises, "max-stretch": self.max_stretch, "J": self.J}[name]


def von_mises(sigma: np.ndarray) -> np.ndarray:
    """√(3/2 s:s) of Cauchy stresses shaped (3, 3, *batch), MPa."""
    trace = np.einsum("ii...->...", sigma)
    s = sigma - trace / 3.0 * np.eye(3).reshape(3, 3, *([1] * (sigma.ndim - 2)))
    return np.sqrt(1.5 * np.einsum("ij...,ij...->...", s, s))


def max_principal_stretch(F: np.ndarray) -> np.ndarray:
    """√ of the largest eigenvalue of C = FᵀF, for F shaped (3, 3, *batch)."""
    C = np.einsum("kI...,kJ...->...IJ", F, F)
    return np.sqrt(np.linalg.eigvalsh(C)[..., -1])


def cell_fields(body, evaluation) -> CellFields:
    """The three fields averaged per cell for a converged state of ``body``. On a 2D sheet they
    are those of the full 3D state F(λ₃) of the plane law (so J = det F̄ λ₃ and σ₃₃ = 0 in plane
    stress)."""
    F, dx = evaluation.F, body.space.dx
    material = getattr(body, "material", None)
    if F.shape[0] == 2:
        F, material = material.full_gradient(F), material.base
    J_q = np.linalg.det(np.moveaxis(F, (0, 1), (-2, -1)))
    if hasattr(body, "cell_cauchy"):
        sigma = body.cell_cauchy(evaluation)
    else:
        sigma = cell_average(cauchy(material.stress(F), F), dx)
    return CellFields(von_mises=von_mises(sigma), max_stretch=cell_average(max_principal_stretch(F), dx),
                      J=cell_average(J_q, dx))
