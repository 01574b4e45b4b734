"""Is the modulus window elastic? A material that yields inside (or before) it has no E to read.

E and ν are the slopes of the elastic part of the curve. With ``[effects.plasticity]`` the run
records, per level, the largest accumulated plastic strain α over the cells; if α > 0 at a level
whose extensometer strain |ε| is still within the modulus window's upper end, the fitted slope
mixes elastic and plastic flow (a yield stress of 1e-6 MPa on E = 10 MPa gave "E = 0.0024 MPa",
and in other cases a negative E) and is not Young's modulus. Such a fit is withdrawn, with the
measured reason: the first such level's strain and α, the yield strain σ_y0 / E, the window.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from vlab.measure.elastic_constants import ElasticConstants

YIELDED = 0.0  # α above this at a level: the material has yielded there


def yield_before_window(strain: list[float], plastic_max: list[float] | None,
                        window: tuple[float, float]) -> tuple[float, float] | None:
    """(|ε|, α) of the first level inside or before the window's end with α > 0, or None."""
    if not plastic_max:
        return None
    eps = np.abs(np.asarray(strain[:len(plastic_max)], float))
    alpha = np.asarray(plastic_max[:len(eps)], float)
    hit = np.flatnonzero((alpha > YIELDED) & (eps <= window[1] * (1 + 1e-9)))
    return None if not hit.size else (float(eps[hit[0]]), float(alpha[hit[0]]))


def withdrawn_if_yielded(constants: ElasticConstants, strain: list[float], plastic_max: list[float] | None,
                         window: tuple[float, float], yield_stress: float, E_input: float) -> ElasticConstants:
    """``constants`` unchanged, or without E and ν and with the note saying why (module docstring)."""
    found = yield_before_window(strain, plastic_max, window)
    if found is None or constants.E is None:
        return constants
    return dataclasses.replace(constants, E=None, nu=None, E_fit=None, nu_fit=None, per_axis=[],
                               note=yield_note(found, window, yield_stress, E_input))


def yield_note(found: tuple[float, float], window: tuple[float, float], yield_stress: float,
               E_input: float) -> str:
    eps, alpha = found
    return (f"not measurable: the material yields before the modulus window ends — plastic strain "
            f"α = {alpha:.3g} already at extensometer strain {eps:.3g} ≤ {window[1]:g} "
            f"(effects.plasticity.yield_stress = {yield_stress:g} MPa, uniaxial yield strain "
            f"σ_y0/E = {yield_stress / E_input:.3g}); the slope there mixes elastic and plastic "
            f"flow, so it is not E (E is read only where the curve is elastic: a modulus window "
            f"below the yield strain)")


def screen_yield(scene, fitted, constants: ElasticConstants, extra: dict) -> ElasticConstants:
    """A run's E, ν (and crosshead modulus in ``extra``) withdrawn when plasticity set in before
    the window ends; ``extra["effects"]`` carries the per-level plastic strain maxima."""
    plastic = scene.effect("plasticity")
    if plastic is None:
        return constants
    alpha = extra["effects"]["history"].get("plastic_strain_max")
    args = (alpha, scene.measure.modulus_window, plastic.yield_stress, scene.material.moduli.E)
    screened = withdrawn_if_yielded(constants, fitted.strain[0], *args)
    crosshead = extra.get("crosshead")
    if screened is not constants and crosshead and crosshead.get("E") is not None:
        extra["crosshead"] = crosshead | {"E": None, "fit": None, "note": screened.note}
    return screened
