"""Analytic homogeneous responses used as the oracle for block tests with roller grips.

With roller grips and free lateral faces a block deforms homogeneously: F = diag(λ, t, t)
(uniaxial, P22 = 0) or diag(λx, λy, t) (biaxial, P33 = 0); the load-cell stress equals P11.
A sheet in plane stress has the same states; in plane strain F₃₃ = 1 (materials.homogeneous).
"""

from __future__ import annotations

import numpy as np

from vlab.materials.homogeneous import InadmissibleState, homogeneous_state


def homogeneous_curve(material, stretches: dict[int, list[float]]) -> dict | None:
    """Nominal stress per axis and lateral stretch at the recorded grip stretches, or None."""
    axes = sorted(stretches)
    out = {f"stress_{'xy'[a]}": [] for a in axes} | {"lateral_stretch": []}
    try:
        for row in zip(*(stretches[a] for a in axes)):
            state = homogeneous_state(material, row)
            for a in axes:
                out[f"stress_{'xy'[a]}"].append(float(state.P[a, a]))
            out["lateral_stretch"].append(float(state.lateral_stretch))
    except InadmissibleState as exc:
        out["note"] = str(exc)
    return out


def relative_error(measured, reference, scale: float | None = None) -> float:
    """max |measured − reference| / max |reference| over the common rows, or / ``scale`` when
    given (the largest reference stress of any axis: an axis whose stress passes through zero,
    or stays there, σ_y ≡ 0 when ε_y = −ν ε_x, has no scale of its own)."""
    n = min(len(measured), len(reference))
    if n == 0:
        return float("nan")
    m, r = np.asarray(measured[:n]), np.asarray(reference[:n])
    denominator = np.max(np.abs(r)) if scale is None else scale
    return float(np.max(np.abs(m - r)) / max(denominator, 1e-300))
