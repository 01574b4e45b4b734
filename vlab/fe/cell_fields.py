"""Quadrature-point stress and its cell averages: what a body keeps per cell of a converged state.

    σ = P Fᵀ / J              Cauchy stress, MPa, J = det F
    v̄_e = Σ_q v dx / Σ_q dx   volume average over the element's reference quadrature weights

Here (not in vlab.post) because the history body keeps its cells' σ at the end of every increment;
vlab.post.fields builds the rendered fields (von Mises, stretch, J) on top of these.
"""

from __future__ import annotations

import numpy as np

from vlab.tensor import det

__all__ = ["cauchy", "cell_average"]


def cell_average(values: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """Volume average over quadrature points: values (..., e, q) with dx (e, q) -> (..., e)."""
    return np.sum(values * dx, axis=-1) / np.sum(dx, axis=-1)


def cauchy(P: np.ndarray, F: np.ndarray) -> np.ndarray:
    """σ = P Fᵀ / J for stacks shaped (3, 3, *batch), MPa."""
    J = det(F)  # closed form, as the solver's J (numpy.linalg.det: a batched LAPACK call, ~10× slower)
    return np.einsum("iJ...,kJ...->ik...", P, F) / J
