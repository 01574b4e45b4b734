"""What a confined-compression test measures (vlab.loading.kinds.confined).

Readings per level, from the FE field over the whole body (the die makes it homogeneous):
- the volume ratio J̄ = ∫ det F dV / V₀ (the current volume over the reference one);
- the pressure p̄ = ∫ p J dV / ∫ J dV, p = −tr σ / 3, σ = P Fᵀ / J (MPa; the current-volume
  average, which is what a pressure transducer in the die wall reads for a uniform state).
Constants over the modulus window (|ε| = |λ − 1| in it, measure/fit.py, with R²):
- the constrained modulus M = slope of the axial nominal stress F/A₀ against the extensometer
  strain ε (small strain: σ₁₁ = (K + 4G/3) ε₁₁ with ε₂₂ = ε₃₃ = 0);
- the bulk modulus K = −slope of p̄ against J̄ − 1 (small strain: p = −K ε_vol);
- G = 3 (M − K) / 4 follows from both, and from them E = 9KG/(3K + G), ν = (3K − 2G)/(2(3K + G)),
  reported as derived (the die does not measure E and ν directly).
"""

from __future__ import annotations

import numpy as np

from vlab.measure.elastic_constants import ElasticConstants
from vlab.measure.fit import FitError, fit_line

__all__ = ["volume_pressure_readers", "confined_constants"]


def volume_pressure_readers(space, specimen, loading, material) -> dict:
    """Readers of J̄ and (with a continuum material) p̄ (module docstring)."""
    w = space.dx
    volume = float(np.sum(w))
    cache: dict = {}

    def fields(level):
        if cache.get("level") is not level:
            F = level.evaluation.F
            J = np.linalg.det(np.moveaxis(F, (0, 1), (-2, -1)))
            cache["level"], cache["J"] = level, J
            if material is not None:
                P = material.stress(F)
                trace_sigma = np.einsum("ij...,ij...->...", P, F) / J  # tr(P Fᵀ) / J
                cache["p"] = float(np.sum(-trace_sigma / 3.0 * J * w) / np.sum(J * w))
        return cache

    readers = {"volume_ratio": lambda level: float(np.sum(fields(level)["J"] * w) / volume)}
    if material is not None:
        readers["pressure"] = lambda level: fields(level)["p"]
    return readers


def confined_constants(curve, window, method) -> ElasticConstants:
    """M and K over the window, and G, E, ν derived from them (module docstring)."""
    note = ("confined compression: E and nu are not measured directly; M = slope of axial stress against "
            "strain, K = -slope of pressure against J - 1; G, E, nu derived from M and K")
    extra: dict = {"constrained_modulus": None, "bulk_modulus": None}
    try:
        m_fit = fit_line(np.array(curve.strain[0]), curve.column("stress", 0), window, method)
        extra |= {"constrained_modulus": m_fit.slope, "constrained_modulus_fit": m_fit.as_dict()}
        if curve.extra.get("pressure"):
            dv = np.array(curve.extra["volume_ratio"]) - 1.0
            k_fit = fit_line(dv, -np.array(curve.extra["pressure"]), window, method)
            extra |= {"bulk_modulus": k_fit.slope, "bulk_modulus_fit": k_fit.as_dict()}
    except FitError as exc:
        note = f"M and K not measured: {exc}"
    M, K = extra["constrained_modulus"], extra["bulk_modulus"]
    if M is not None and K is not None:
        G = 0.75 * (M - K)
        extra |= {"G_derived": G}
        if G > 0 and K > 0:
            extra |= {"E_derived": 9 * K * G / (3 * K + G), "nu_derived": (3 * K - 2 * G) / (2 * (3 * K + G))}
    at_end = {"stretch_at_end": curve.stretch[0][-1] if curve.t else None,
              "volume_ratio_at_end": curve.extra["volume_ratio"][-1] if curve.extra.get("volume_ratio") else None,
              "pressure_at_end": curve.extra["pressure"][-1] if curve.extra.get("pressure") else None}
    return ElasticConstants(None, None, None, None, [{"axis": "x", "M": M, "K": K}], note, extra | at_end)
