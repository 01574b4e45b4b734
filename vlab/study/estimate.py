"""A run's own accuracy estimate from one coarser companion solve (Richardson-type).

The companion is the same scene with mesh.size (and mesh.gauge_size) multiplied by r = 2 (capped
at the largest specimen dimension, the actual ratio is used). With q_h the run's value and q_rh the
companion's, and the discretization error assumed to behave as C h^p,
    error(q_h) ≈ |q_h − q_rh| / (r^p − 1),
taking p = the element order (stress-like quantities converge at least that fast in the
displacement formulation; functionals such as the reaction force faster, so this overestimates
their error: a conservative figure). Quantities: E, ν, final engineering stress.
When both values agree to round-off the estimate is zero by construction, not by luck: it is
flagged ``exact_by_construction`` (the roller block, whose homogeneous state every mesh represents
exactly). The companion's wall time is reported as the estimate's cost.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from vlab.loading.kinds import KINDS
from vlab.scene import Scene, SceneError, apply_overrides, parse_scene

log = logging.getLogger(__name__)

COARSENING = 2.0
ROUND_OFF = 1e-10
QUANTITIES = ("E", "nu", "final_stress")


def companion_scene(scene: Scene, factor: float = COARSENING) -> Scene:
    size = min(scene.mesh.size * factor, scene.specimen.max_dimension)
    over: dict = {"mesh.size": size}
    if scene.mesh.gauge_size is not None:
        over["mesh.gauge_size"] = min(scene.mesh.gauge_size * factor, size)
    # the companion compares E, ν and the stress only: no camera, no DIC
    source = {k: v for k, v in scene.source.items() if k != "instruments"}
    return parse_scene(apply_overrides(source, over), origin="accuracy-estimate companion",
                       base_dir=scene.base_dir)


def _values(result) -> dict:
    """E, ν and the stress at the peak grip stretch or shear (``peak_level``: the last reading of a monotonic test; a
    cyclic or load–unload test ends unloaded, where a relative error means nothing)."""
    stress = result.curve.column("stress", 0) if result.curve.t else []
    if not len(stress):
        return {"E": result.constants.E, "nu": result.constants.nu, "final_stress": None}
    peak = peak_level(result.curve)
    return {"E": result.constants.E, "nu": result.constants.nu, "final_stress": float(stress[peak])}


def peak_level(curve) -> int:
    """The level of the largest deformation: the largest |c − c₀| of the kind's control column
    (the grip stretch, at rest 1; the shear γ or the twist ψ, at rest 0)."""
    # not the load parameter t: a load-unload or cyclic record's t rises while the stretch falls
    kind = KINDS.get(curve.kind)
    rest = kind.rest if kind is not None else 1.0
    return int(np.argmax(np.abs(np.asarray(curve.stretch[0], dtype=float) - rest)))


def _estimates(fine: dict, rough: dict, ratio: float, order: int) -> tuple[dict, bool]:
    """Per quantity the fine and companion values and err = |q_h − q_rh| / (r^p − 1), absolute
    and relative; and whether every pair agrees to round-off (the estimate is then zero by
    construction, not a measured convergence)."""
    quantities, exact = {}, True
    for q in QUANTITIES:
        a, b = fine[q], rough[q]
        if a is None or b is None:
            quantities[q] = {"value": a, "companion": b, "error": None, "relative": None}
            continue
        diff = abs(a - b)
        exact &= diff <= ROUND_OFF * max(abs(a), 1e-300)
        err = diff / (ratio**order - 1.0)
        quantities[q] = {"value": a, "companion": b, "error": err, "relative": err / abs(a) if a else None}
    return quantities, exact


def accuracy_estimate(result) -> dict:
    """The estimate for a finished RunResult (a JSON-safe dict; ``available`` False with a reason)."""
    from vlab.run import run_scene

    scene = result.scene
    out = {"method": f"one companion solve with mesh.size × {COARSENING:g}; error ≈ |q_h − q_2h| / (r^p − 1), "
                     f"p = element order (assumed, conservative)",
           "assumed_order": scene.mesh.order, "available": False}
    if not result.converged:
        return out | {"reason": "the run itself did not complete"}
    if scene.specimen.shape == "mesh":
        return out | {"reason": "the mesh is imported (specimen.shape = 'mesh'): vlab cannot coarsen a user's mesh"}
    start = time.perf_counter()
    try:
        coarse_scene = companion_scene(scene)
        if coarse_scene.mesh.size <= scene.mesh.size:
            return out | {"reason": "the mesh is already as coarse as the specimen allows"}
        coarse = run_scene(coarse_scene)
    except SceneError as exc:
        return out | {"reason": f"the coarser companion mesh is not usable: {exc}",
                      "cost_s": time.perf_counter() - start}
    cost = time.perf_counter() - start
    if not coarse.converged:
        return out | {"reason": f"the companion solve stopped: {coarse.history.failure.reason}", "cost_s": cost}
    ratio = coarse_scene.mesh.size / scene.mesh.size
    quantities, exact = _estimates(_values(result), _values(coarse), ratio, scene.mesh.order)
    note = ("both solves agree to round-off: the estimate is zero by construction (the test's state is "
            "represented exactly by every mesh, e.g. the homogeneous roller block), not a measured "
            "convergence" if exact else "")
    return out | {"available": True, "companion_mesh_size": coarse_scene.mesh.size, "ratio": ratio,
                  "companion_dofs": int(coarse.space.n_dofs), "cost_s": cost, "quantities": quantities,
                  "exact_by_construction": exact, "note": note}
