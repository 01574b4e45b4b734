"""One whole vlab test at given material constants, with the exact sensitivities of its readings.

The test runs once (vlab.run.run_scene) with an observer (vlab.identify.fe_levels) that, at every
recorded level, differentiates the converged equilibrium with respect to the fitted constants:
K_ff du_f/dp_j = −∂f_int,f/∂p_j with the factorization of K_ff the step already has (the stability
monitor's, which the stepper reuses for the next predictor), one back-substitution per constant,
pushed through each channel's instruments (vlab.identify.fe_readings: the load cell and the
extensometer of each loading axis of an extension test, the torque and the axial force or the
free end's stretch of torsion, the cavity's or the liquid's pressure against the inflation's
stretch, volume ratio or pole height, the die's stress). ∂P/∂p for every model of the library by
the complex step on the principal stresses (vlab.identify.fe_stress). ``Simulation.factorizations``
is the run's own count (the stepper's and the monitor's), ``sensitivity_factorizations`` the ones
the sensitivities added (0 when the monitor's factor is reused), ``sensitivity_solves`` their
back-substitutions.
"""

from __future__ import annotations

import copy
import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vlab.fields import SceneError
from vlab.identify.fe_readings import channels_of

__all__ = ["Simulation", "simulate", "run_quietly", "MODULUS_KEYS"]

MODULUS_KEYS = ("E", "nu", "lambda", "mu", "G", "K", "M")


@dataclass(frozen=True)
class Simulation:
    """Readings at every recorded level (k) and channel (a; vlab.identify.fe_readings): ``strain``
    (k, a) the channel's control (an extension test's extensometer strain, a twist, a stretch, ...),
    ``force`` (k, a) its reading (N, N·mm, MPa, ...), and their sensitivities (k, a, n_p); area0 (a,)
    the load cells' sections (mm²) of the channels' axes."""

    strain: np.ndarray
    force: np.ndarray
    dstrain: np.ndarray
    dforce: np.ndarray
    area0: np.ndarray
    warnings: tuple = ()
    cached: bool = False
    dofs: int = 0
    counts: dict = field(default_factory=dict)  # factorizations, sensitivity_factorizations, ...

    def as_dict(self) -> dict:
        """A cache entry (vlab.study.cache validates its version and status)."""
        from vlab import __version__

        return {"vlab_version": __version__, "status": "ok", "strain": self.strain.tolist(),
                "force": self.force.tolist(), "dstrain": self.dstrain.tolist(),
                "dforce": self.dforce.tolist(), "area0": self.area0.tolist(), "warnings": list(self.warnings),
                "dofs": self.dofs, "counts": self.counts}

    @classmethod
    def from_dict(cls, d: dict) -> "Simulation":
        return cls(np.array(d["strain"]), np.array(d["force"]), np.array(d["dstrain"]), np.array(d["dforce"]),
                   np.array(d["area0"]), tuple(d["warnings"]), True, int(d["dofs"]), dict(d["counts"]))


CARD_KEYS = ("C10", "C01", "C20", "C30", "D1", "mu", "alpha", "Jm", "lambda_m", "volumetric")


def material_table(fe: dict, values: dict) -> dict:
    """The scene's [material] table with its constants replaced by ``values`` (flat names)."""
    from vlab.identify.fe_stress import card_table

    raw = fe["scene_raw"]["material"]
    table = {k: v for k, v in raw.items() if k not in MODULUS_KEYS + CARD_KEYS}
    if fe.get("volumetric") and fe.get("model", "neo-hookean") != "neo-hookean":
        table["volumetric"] = fe["volumetric"]
    return table | card_table(values)


def scene_with(fe: dict, values: dict):
    """The fit's scene with its material constants replaced by ``values`` and without a camera
    ([instruments.dic]: the loop needs the readings and the displacement, and rendering and
    correlating every trial made a 7 s field fit take 40 s)."""
    from vlab.scene import parse_scene

    raw = copy.deepcopy(fe["scene_raw"])
    raw["material"] = material_table(fe, values)
    if isinstance(raw.get("instruments"), dict):
        raw["instruments"].pop("dic", None)
    return parse_scene(raw, "fe.scene", Path(fe["scene_path"]).parent)


class _Quiet(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return record.levelno > logging.WARNING


CACHE_FORMAT = 3  # entries per channel (control, reading), with the factorization counts


def simulate(fe: dict, values: dict, refactorize: bool = False, run=None) -> Simulation:
    """Run the scene at ``values`` and differentiate its readings (RuntimeError if the test fails).

    With ``fe["cache"]`` (a folder) the readings and sensitivities are kept in vlab's run cache
    (vlab.study.cache: content-addressed by the scene with these constants, the vlab version, the
    fitted constants' names and the channels), so a repeated fit re-solves nothing. ``run(fe, values)``
    computes a miss elsewhere (vlab.identify.fe_dask: on a Dask cluster); the cache stays here.
    ``refactorize``: the sensitivities assemble and factorize K at each level themselves (the A/B
    count only; never cached)."""
    scene = scene_with(fe, values)
    cache = key = None
    if fe.get("cache") and not refactorize:
        from vlab.study.cache import SummaryCache, cache_key

        cache = SummaryCache(fe["cache"])
        key = cache_key(scene.content_hash(), {"identify.fe_sensitivity": list(fe["parameters"]),
                                               "channels": [list(c) for c in channels_of(fe)],
                                               "format": CACHE_FORMAT})
        hit = cache.get(key)
        if hit is not None:
            return Simulation.from_dict(hit)
    sim = _solve(fe, scene, values, refactorize) if run is None else run(fe, values)
    if cache is not None:
        cache.put(key, sim.as_dict())
    return sim


def run_quietly(fe: dict, scene, values: dict, observe):
    """vlab.run.run_scene(scene, observe=observe) with the run's log quiet (its caveats go to
    fit.json once, not to the console per solve); RuntimeError if the test did not complete."""
    from vlab.run import run_scene

    run_log = logging.getLogger("vlab.run")
    quiet = _Quiet()
    run_log.addFilter(quiet)
    try:
        result = run_scene(scene, observe=observe)
    finally:
        run_log.removeFilter(quiet)
    if not result.converged:
        raise RuntimeError(f"the test at {material_table(fe, values)} did not complete: "
                           f"{result.history.failure.reason}")
    return result


def _solve(fe: dict, scene, values: dict, refactorize: bool) -> Simulation:
    from vlab.identify.fe_levels import LevelSensitivities
    from vlab.identify.fe_readings import quantities

    channels = quantities(fe, scene)
    made: list[LevelSensitivities] = []

    def observe(prepared, tangents):
        made.append(LevelSensitivities(prepared, tangents, fe, values, channels, refactorize))
        return made[-1]

    result = run_quietly(fe, scene, values, observe)
    sens, curve = made[0], result.curve
    if len(curve.t) != len(sens.rows):
        raise SceneError("fe.scene: the recorded levels and the solver's levels differ")
    counts = {"factorizations": int(result.history.factorizations),
              "sensitivity_factorizations": sens.factorizations, "sensitivity_solves": sens.solves,
              "levels": len(sens.rows), "levels_with_the_monitors_factor": sens.reused}
    # the run's count includes a factor the observer asked the monitor's cache for; not its own ones
    counts["total_factorizations"] = counts["factorizations"] + (sens.factorizations if refactorize else 0)
    return Simulation(np.array([np.asarray(c.value(curve), float) for c, _ in channels]).T,
                      np.array([np.asarray(r.value(curve), float) for _, r in channels]).T,
                      np.array([r[1] for r in sens.rows]), np.array([r[0] for r in sens.rows]),
                      np.array([float(curve.area0.get(r.axis, np.nan)) for _, r in channels]),
                      tuple(result.diagnostics.warnings), False, int(result.space.n_dofs), counts)
