"""Where one model's stress–strain curve departs from a reference model's (the compare report).

    departure(θ) = first extensometer strain with |s − s_ref| / |s_ref| ≥ θ

s the engineering stress (MPa) at the same grip stretch, level by level, linearly interpolated
between levels; thresholds θ = 5 % and 10 % by default.
"""

from __future__ import annotations

import numpy as np

__all__ = ["REFERENCE_MODEL", "departure_strains"]

REFERENCE_MODEL = "neo-hookean"  # the model the others are measured against


def departure_strains(reference: dict, other: dict, thresholds=(0.05, 0.10)) -> dict[str, float | None]:
    """Extensometer strain at which ``other``'s engineering stress first differs from
    ``reference``'s by each relative threshold, |s − s_ref| / |s_ref|, compared level by level at
    the same grip stretch and interpolated linearly between levels; None if it never does."""
    s_ref, s = np.asarray(reference["curve"]["stress"]), np.asarray(other["curve"]["stress"])
    strain = np.asarray(other["curve"]["strain"])
    n = min(len(s_ref), len(s))
    rel = np.abs(s[:n] - s_ref[:n]) / np.maximum(np.abs(s_ref[:n]), 1e-300)
    out: dict[str, float | None] = {}
    for threshold in thresholds:
        above = np.flatnonzero(rel >= threshold)
        key = f"{round(threshold * 100):d}%"
        if len(above) == 0:
            out[key] = None
        elif above[0] == 0:
            out[key] = float(strain[0])
        else:
            i = above[0]
            w = (threshold - rel[i - 1]) / (rel[i] - rel[i - 1])
            out[key] = float(strain[i - 1] + w * (strain[i] - strain[i - 1]))
    return out
