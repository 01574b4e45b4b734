"""One whole vlab test at given material constants, with the exact sensitivities of its readings.

At a converged state the residual r(u, p) = f_int(u; p) − f_reaction vanishes on the free DOFs;
differentiating at fixed grip displacement gives, for each constant p_j,
    K_ff du_f/dp_j = −∂f_int,f/∂p_j        (du/dp = 0 on the prescribed DOFs)
with K the tangent at that state, and the instruments' readings follow:
    load cell    dF/dp = c Σ_grip (∂f_int/∂p + K_{grip,f} du_f/dp)      (c the symmetry factor)
    extensometer de/dp = n · (δx_b − δx_a) / L0, δx = the marks' displacement along du/dp,
                 n the unit vector between the marks (the reading |x_b − x_a|/L0 − 1 is smooth).
For the compressible Neo-Hookean law, P = μ (F − F⁻ᵀ) + λ_L ln J F⁻ᵀ with λ_L = K − 2μ/3, so
    ∂P/∂μ|_K = F − F⁻ᵀ − (2/3) ln J F⁻ᵀ,   ∂P/∂K|_μ = ln J F⁻ᵀ    (MPa per MPa)
and ∂f_int/∂p is the internal force of that stress field (P is linear in μ and K: exact). The card
models fitted here (Mooney–Rivlin, Yeoh: P = Σ_j p_j P_j(F), linear in each of C10, C01, C20,
C30 and K) get ∂P/∂p_j = (P(p + δ e_j) − P(p))/δ from the library's own stress, which is exact for
a linear dependence (no truncation error, whatever δ; δ = max(|p_j|, 1e-3) keeps the card admissible).
K_ff is factorized once per recorded level (the stepping does not hand its own factor out), and
each constant costs one back-substitution there.
"""

from __future__ import annotations

import copy
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vlab.fields import SceneError

__all__ = ["Simulation", "simulate", "MODULUS_KEYS"]

MODULUS_KEYS = ("E", "nu", "lambda", "mu", "G", "K", "M")


@dataclass(frozen=True)
class Simulation:
    """Readings (strain, force N) at every recorded level and their sensitivities (k, n_p)."""

    strain: np.ndarray
    force: np.ndarray
    dstrain: np.ndarray
    dforce: np.ndarray
    area0: float
    warnings: tuple = ()
    cached: bool = False
    dofs: int = 0

    def as_dict(self) -> dict:
        """A cache entry (vlab.study.cache validates its version and status)."""
        from vlab import __version__

        return {"vlab_version": __version__, "status": "ok", "strain": self.strain.tolist(),
                "force": self.force.tolist(), "dstrain": self.dstrain.tolist(),
                "dforce": self.dforce.tolist(), "area0": self.area0, "warnings": list(self.warnings), "dofs": self.dofs}

    @classmethod
    def from_dict(cls, d: dict) -> "Simulation":
        return cls(np.array(d["strain"]), np.array(d["force"]), np.array(d["dstrain"]), np.array(d["dforce"]),
                   float(d["area0"]), tuple(d["warnings"]), True, int(d["dofs"]))


CARD_KEYS = ("C10", "C01", "C20", "C30", "D1")


def material_table(fe: dict, values: dict) -> dict:
    """The scene's [material] table with its constants replaced by ``values``."""
    raw = fe["scene_raw"]["material"]
    table = {k: v for k, v in raw.items() if k not in MODULUS_KEYS + CARD_KEYS}
    return table | {k: float(v) for k, v in values.items()}


def scene_with(fe: dict, values: dict):
    """The fit's scene with its material constants replaced by ``values``."""
    from vlab.scene import parse_scene

    raw = copy.deepcopy(fe["scene_raw"])
    material = material_table(fe, values)
    raw["material"] = material
    return parse_scene(raw, "fe.scene", Path(fe["scene_path"]).parent)


def _stress_derivatives(F: np.ndarray, fe: dict, values: dict) -> dict:
    """∂P/∂p (3, 3, e, q) for every fitted constant (module docstring)."""
    if fe.get("model", "neo-hookean") == "neo-hookean":
        from vlab.tensor import inv_transpose

        Finv_t, J = inv_transpose(F)
        lnJ = np.log(J)
        return {"mu": F - Finv_t - (2.0 / 3.0) * lnJ * Finv_t, "K": lnJ * Finv_t}
    from vlab.materials.card import build_material, parse_material  # the FE model library (#18)

    def stress(v):
        return build_material(parse_material(material_table(fe, v))).stress(F)

    P0 = stress(values)
    out = {}
    for p in fe["parameters"]:
        delta = max(abs(values[p]), 1e-3)
        out[p] = (stress(values | {p: values[p] + delta}) - P0) / delta
    return out


def _marks_displacement(ext, du: np.ndarray) -> np.ndarray:
    """δx of both marks along du (the probe is linear; reflections only flip components)."""
    from vlab.geometry.symmetry import reflect_back

    dim = ext._dim
    d = ext._probe @ du.reshape(-1, dim)
    zero = np.zeros(dim)
    return np.array([reflect_back(ext._X[i] + d[i], ext._signs[i], ext._planes)
                     - reflect_back(ext._X[i] + zero, ext._signs[i], ext._planes) for i in (0, 1)])


def _level_sensitivity(level, body, space, free, grip, factor, ext, fe, values):
    from vlab.fe.assembly import element_forces, scatter_vector
    from vlab.fe.linsolve import factorize

    ev = level.evaluation
    K = body.stiffness(ev).tocsr()
    Kff, Kgf = K[free][:, free], K[grip][:, free]
    fac = factorize(Kff)
    dP = _stress_derivatives(ev.F, fe, values)
    params = fe["parameters"]
    from vlab.geometry.symmetry import reflect_back

    x = ext._X + ext._probe @ ev.u.reshape(-1, ext._dim)
    n = (reflect_back(x[1], ext._signs[1], ext._planes) - reflect_back(x[0], ext._signs[0], ext._planes))
    n = n / np.linalg.norm(n)
    dF, de = [], []
    for p in params:
        g = scatter_vector(space, element_forces(space, dP[p]))
        du_f = -fac.solve(g[free])
        dF.append(factor * float(g[grip].sum() + (Kgf @ du_f).sum()))
        du = np.zeros(space.n_dofs)
        du[free] = du_f
        dx = _marks_displacement(ext, du)
        de.append(float(n @ (dx[1] - dx[0])) / ext.length0)
    return dF, de


class _Quiet(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return record.levelno > logging.WARNING


def simulate(fe: dict, values: dict) -> Simulation:
    """Run the scene at ``values`` and differentiate its readings (RuntimeError if the test fails).

    With ``fe["cache"]`` (a folder) the readings and sensitivities are kept in vlab's run cache
    (vlab.study.cache: content-addressed by the scene with these constants, the vlab version and
    the fitted constants' names), so a repeated fit re-solves nothing."""
    scene = scene_with(fe, values)
    if not fe.get("cache"):
        return _solve(fe, scene, values)
    from vlab.study.cache import SummaryCache, cache_key

    cache = SummaryCache(fe["cache"])
    key = cache_key(scene.content_hash(), {"identify.fe_sensitivity": list(fe["parameters"])})
    hit = cache.get(key)
    if hit is not None:
        return Simulation.from_dict(hit)
    sim = _solve(fe, scene, values)
    cache.put(key, sim.as_dict())
    return sim


def _solve(fe: dict, scene, values: dict) -> Simulation:
    from vlab.loading.grips import grip_loading
    from vlab.measure.instruments import extensometers
    from vlab.run import run_scene

    run_log = logging.getLogger("vlab.run")
    quiet = _Quiet()
    run_log.addFilter(quiet)  # the run's caveats go to fit.json once, not to the console per solve
    try:
        result = run_scene(scene)
    finally:
        run_log.removeFilter(quiet)
    if not result.converged:
        raise RuntimeError(f"the test at {scene.material.moduli} did not complete: {result.history.failure.reason}")
    space, specimen = result.space, result.specimen
    body, partition = result.solver.body, result.solver.partition
    loading = grip_loading(specimen, space.node_coordinates, scene.test.stretch, scene.test.grips)
    grip, factor = loading.moving_dofs[0], specimen.force_factor(0)
    ext = extensometers(space, [specimen.extensometers[0]], specimen.symmetry)[0]
    rows = [_level_sensitivity(lv, body, space, partition.free, grip, factor, ext, fe, values)
            for lv in result.history.levels]
    curve = result.curve
    if len(curve.strain[0]) != len(rows):
        raise SceneError("fe.scene: the recorded levels and the solver's levels differ")
    return Simulation(np.array(curve.strain[0]), np.array(curve.force[0]),
                      np.array([r[1] for r in rows]), np.array([r[0] for r in rows]),
                      float(curve.area0[0]), tuple(result.diagnostics.warnings), False, int(space.n_dofs))
