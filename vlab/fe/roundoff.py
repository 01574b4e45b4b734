"""The round-off floor of Newton's residual, and whether a stalled solve has reached it.

F = I + ∇u is formed in double precision, so at best each entry of F is known to ε = 2.2e-16
(F ≈ I): the same as every nodal displacement known only to δu ≈ ε h (h the element size, mm).
A residual below what such a perturbation produces cannot be reached, whatever the solver does:
    floor ≈ ‖K_ff d‖ / scale,   d_i = ε h s_i (random signs s_i),   scale = the residual's force
scale (the grip reaction, N). Relative to the reaction the floor is ~ε / (grip strain): 1e-11 at a
strain of 1e-5, so a tight solver.rtol fails first on the smallest (cut-back) substeps. Measured on
the ISO 527-2 1BA dogbone (Neo-Hookean): floor 1.3e-11 where its first level reached 3.9e-12, and
on a 10 mm block at grip strain 1e-5 Newton stalls at 1.3e-11 against an estimate of the same order.
"""

from __future__ import annotations

import numpy as np

EPS = float(np.finfo(float).eps)
STALL_WINDOW = 5  # a stall: the last STALL_WINDOW residuals fail to halve the best one before them
NEAR_FLOOR = 100.0  # a stall within this factor of the floor estimate is the floor, not a bug


def element_size(space) -> float:
    """Median largest coordinate span of an element's nodes, mm."""
    X = space.node_coordinates[space.element_nodes]  # (e, a, dim)
    return float(np.median(np.ptp(X, axis=1).max(axis=1)))


def roundoff_floor(body, partition, evaluation, scale: float) -> float | None:
    """The relative residual a perturbation of every free DOF by ε h produces (module docstring);
    None if the tangent cannot be assembled here."""
    try:
        Kff = partition.blocks(body.stiffness(evaluation))[0]
    except Exception:  # the floor is a diagnosis only: never let it mask the failure it explains
        return None
    d = EPS * element_size(body.space) * np.random.default_rng(0).choice([-1.0, 1.0], Kff.shape[0])
    return float(np.linalg.norm(Kff @ d) / scale) if scale > 0 else None


def stalled(residuals: list[float]) -> bool:
    """The last STALL_WINDOW residuals never halve the best one reached before them."""
    if len(residuals) <= STALL_WINDOW:
        return False
    return min(residuals[-STALL_WINDOW:]) >= 0.5 * min(residuals[:-STALL_WINDOW])


def stall_explanation(residuals: list[float], rtol: float, floor: float | None) -> str:
    """The words for a Newton solve that ran out of iterations: '' unless it stalled at the
    round-off floor (then what was measured: where it stalled, the floor, the tolerance)."""
    if floor is None or not stalled(residuals) or min(residuals) > NEAR_FLOOR * floor:
        return ""
    return (f": the relative residual stalls at {min(residuals):.3g} (no halving in its last "
            f"{STALL_WINDOW} iterations), at the round-off floor of this problem (floor ≈ {floor:.2g} "
            f"here: the residual of perturbing every DOF by ε × element size, relative to the grip "
            f"reaction; it falls as the grip strain grows); solver.rtol = {rtol:g} is "
            f"{'below it' if rtol < floor else 'too close to it'}: the tolerance cannot be met "
            f"reliably in double precision, set solver.rtol well above the floor")
