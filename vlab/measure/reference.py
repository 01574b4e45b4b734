"""Helpers of the analytic reference curves (the oracles are the test kinds' ``state`` and
``reference``: vlab.loading.kinds, from vlab.materials.homogeneous).

With roller grips and free lateral faces a block deforms homogeneously: F = diag(λ, t, t)
(uniaxial, P22 = 0), diag(λx, λy, t) (biaxial, P33 = 0) or diag(λ, 1, t) (planar); the load-cell
stress equals P11. A block whose whole boundary follows x = X + γ Y e₁ is in simple shear.
"""

from __future__ import annotations

import numpy as np


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
