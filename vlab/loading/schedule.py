"""Load schedules: the levels t (grip stretch λ(t) = 1 + t (λ_target − 1)) at which the test
machine records a reading.

A real machine logs continuously, so the modulus is fitted from many readings at small strain.
The schedule mimics that: besides the ``steps`` equal increments to the target it inserts
``modulus_points`` levels spanning the modulus window (half its lower bound to 1.5 times its
upper bound, in grip strain), wherever the first regular step would overshoot the window.
"""

from __future__ import annotations

import numpy as np


def monotonic_schedule(stretch: tuple[float, ...], steps: int, window: tuple[float, float],
                       modulus_points: int = 9) -> np.ndarray:
    """Increasing levels in (0, 1], ending at 1."""
    regular = np.arange(1, steps + 1) / steps
    largest_strain = max(abs(s - 1.0) for s in stretch)
    if modulus_points <= 0 or largest_strain == 0.0:
        return regular
    extra = np.linspace(0.5 * window[0], 1.5 * window[1], modulus_points) / largest_strain
    extra = extra[(extra > 0) & (extra < regular[0] * (1 - 1e-9))]
    return np.concatenate([extra, regular])
