"""Helpers of the analytic reference curves (the oracles are the test kinds' ``state`` and
``reference``: vlab.loading.kinds, from vlab.materials.homogeneous).

With roller grips and free lateral faces a block deforms homogeneously: F = diag(λ, t, t)
(uniaxial, P22 = 0), diag(λx, λy, t) (biaxial, P33 = 0) or diag(λ, 1, t) (planar); the load-cell
stress equals P11. A block whose whole boundary follows x = X + γ Y e₁ is in simple shear.
"""

from __future__ import annotations

import numpy as np


def relative_error(measured, reference) -> float:
    """max |measured − reference| / max |reference| over the common rows."""
    n = min(len(measured), len(reference))
    if n == 0:
        return float("nan")
    m, r = np.asarray(measured[:n]), np.asarray(reference[:n])
    return float(np.max(np.abs(m - r)) / max(np.max(np.abs(r)), 1e-300))
