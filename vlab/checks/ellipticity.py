"""Strong ellipticity of the material tangent: is an instability the material's or the structure's?

The tangent A_iJkL = ∂P_iJ/∂F_kL is strongly elliptic at a point iff the acoustic tensor
    Q_ik(N) = A_iJkL N_J N_L
is positive definite for every unit direction N (reference configuration). Where it is not, the
material itself admits a deformation band normal to N at no energy cost (St. Venant–Kirchhoff in
compression near stretch 0.59): a loss of positive definiteness of K_ff there is a material
instability, whose discrete mode depends on the mesh. While A stays strongly elliptic everywhere,
the instability belongs to the structure (buckling).

Checked on N_DIRECTIONS directions spread evenly over the half sphere (±N give the same Q), so
the minimum found is an upper bound of the true one: a violation confined to a narrow cone of
directions between the samples can be missed.
"""

from __future__ import annotations

import numpy as np

N_DIRECTIONS = 64


def half_sphere_directions(n: int = N_DIRECTIONS) -> np.ndarray:
    """(n, 3) unit vectors with z >= 0 on a Fibonacci spiral (nearly uniform spacing)."""
    k = np.arange(n) + 0.5
    z = 1.0 - k / n
    phi = np.pi * (3.0 - np.sqrt(5.0)) * k
    r = np.sqrt(1.0 - z**2)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


def non_elliptic_fraction(A: np.ndarray, directions: np.ndarray | None = None) -> float:
    """Share of the points of A (shape (3, 3, 3, 3, *batch)) where Q(N) fails to be positive
    definite for some sampled N (0 = strongly elliptic everywhere). Positive definiteness of each
    3×3 Q by its leading principal minors (Sylvester's criterion): cheap for every quadrature
    point of a large mesh."""
    directions = half_sphere_directions() if directions is None else directions
    A = A.reshape(3, 3, 3, 3, -1)
    lost = np.zeros(A.shape[-1], dtype=bool)
    for N in directions:
        Q = np.einsum("iJkLp,J,L->ikp", A, N, N)
        Q = 0.5 * (Q + Q.transpose(1, 0, 2))
        m2 = Q[0, 0] * Q[1, 1] - Q[0, 1] ** 2
        lost |= (Q[0, 0] <= 0.0) | (m2 <= 0.0) | (np.linalg.det(np.moveaxis(Q, -1, 0)) <= 0.0)
    return float(np.mean(lost)) if lost.size else 0.0


def min_acoustic_eigenvalue(A: np.ndarray, directions: np.ndarray | None = None) -> float:
    """Smallest eigenvalue of Q(N) over the sampled directions and all points of A
    (shape (3, 3, 3, 3, *batch)), MPa; ≤ 0 means strong ellipticity is lost somewhere."""
    directions = half_sphere_directions() if directions is None else directions
    A = A.reshape(3, 3, 3, 3, -1)
    lowest = np.inf
    for N in directions:
        Q = np.einsum("iJkLp,J,L->pik", A, N, N)
        lowest = min(lowest, float(np.linalg.eigvalsh(0.5 * (Q + Q.transpose(0, 2, 1)))[:, 0].min()))
    return lowest
