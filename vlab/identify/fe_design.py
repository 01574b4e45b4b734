"""FE-in-the-loop test design: the Fisher information of a card's constants from vlab's own virtual
test of a specimen (``vlab design`` on a fit file with a ``kind = "specimen"`` data set).

A candidate specimen test t is a scene (the fit file's fe.scene or another specimen file), an
extensometer gauge length G (mm) and an extensometer strain range [e_lo, e_hi] read at n evenly
spaced strains e_i. The scene is run once at the card's constants p (vlab.identify.fe_sensitivity.
simulate: the load cell's force F (N) and the extensometer strain e at every recorded level with
their exact sensitivities, one back-substitution per constant with the step's own factorization).
The lab records the force at the strains e_i, F(e_i) from the cubic spline through the levels; its
sensitivity at fixed strain is S_i = dF/dp − F'(e) de/dp (the strain itself moves with p between
clamped grips) — the rows vlab fit's Levenberg–Marquardt uses (vlab.identify.fe_loop.residuals).
With the fit's residual convention (relative: r_i = (F_i − F̂_i)/max(|F̂_i|, 0.01 max|F̂|), absolute:
r_i = F_i − F̂_i in N) and the readings' scatter s,

    F_t = J_tᵀ J_t / s²,   J_t = ∂r/∂p = S_i / scale_i      (n × n_p; a cruciform: 2n rows)

and from there as for homogeneous tests (vlab.identify.design.assess): Cov = F⁻¹, standard errors,
correlations, D, A, verdict. A cruciform's y readings are taken at the instants the x extensometer
reads e_i (the y strain interpolated along the path by a cubic spline).

An extensometer whose elongation reading scatters (sd σ_u mm, independent readings) reads the
strain with sd σ_u/G: the gauge length's effect. Each reading's residual then has the variance
s² + (F'(e_i) σ_u/(G scale_i))² (F' = dF/de), and its row enters F_t with the weight s²/that
(the effective-variance form of the Fisher information for errors in both variables, to first
order). Without it (σ_u = 0, the default) the gauge length matters only through the strain field
the marks see.

Shorter ranges (the same start, a quarter to all of the range) reuse the run: the test is
hyperelastic and quasi-static, so its states up to a smaller strain are those of the longer run.
"""

from __future__ import annotations

import copy
import dataclasses
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicSpline

from vlab.fields import SceneError
from vlab.identify.datasets import Dataset
from vlab.identify.fe_loop import residuals
from vlab.identify.fe_sensitivity import simulate
from vlab.identify.fe_spec import check_scene, load_scene

__all__ = ["SpecimenTest", "check_designable", "DESIGNED_KINDS", "SpecimenRun", "specimen_candidates", "specimen_runs", "specimen_rows", "strain_noise_weights", "data_rows",
           "strain_range"]


@dataclass(frozen=True)
class SpecimenTest:
    """One candidate FE test: ``scene`` (file) with an extensometer of ``gauge_length`` mm, read at
    ``points`` strains evenly spaced over [lo, hi] (extensometer strain, axis x)."""

    scene: str
    name: str
    kind: str
    shape: str
    gauge_length: float
    lo: float
    hi: float
    points: int = 20

    @property
    def label(self) -> str:
        return (f"specimen {self.name} ({self.kind}, {self.shape}, gauge {self.gauge_length:.4g} mm) "
                f"strain {self.lo:.3g}..{self.hi:.3g}")

    def record(self) -> dict:
        return {"kind": "specimen", "scene": self.scene, "test": self.kind, "shape": self.shape,
                "gauge_length_mm": self.gauge_length, "range": [self.lo, self.hi],
                "range_of": "extensometer strain", "points": self.points}


@dataclass(frozen=True)
class SpecimenRun:
    """A candidate scene with its gauge length, run once at the card's constants."""

    test: SpecimenTest
    sim: object  # vlab.identify.fe_sensitivity.Simulation
    seconds: float

    def describe(self) -> dict:
        s = self.sim
        return {"scene": self.test.scene, "test": self.test.kind, "shape": self.test.shape,
                "gauge_length_mm": self.test.gauge_length, "area0_mm2": s.area0.tolist(), "dofs": s.dofs,
                "levels": int(len(s.strain)), "end_strain": s.strain[-1].tolist(), "from_cache": bool(s.cached),
                "seconds": self.seconds}


def _with_gauge(raw: dict, shape: str, gauge: float) -> dict:
    """The raw scene with its extensometer's gauge length set: a dog-bone's marks are a dimension
    of the specimen (specimen.gauge_length), every other shape's are measure.gauge_length."""
    raw = copy.deepcopy(raw)
    table = "specimen" if shape == "dogbone" else "measure"
    raw.setdefault(table, {})["gauge_length"] = float(gauge)
    return raw


DESIGNED_KINDS = ("uniaxial", "planar", "biaxial")


def check_designable(scene, label: str) -> None:
    """The candidates are extension tests (gauge lengths, extensometer strain ranges): test.kind in
    DESIGNED_KINDS (vlab fit also fits torsion, inflation and the die; vlab design does not plan them)."""
    if scene.test.kind not in DESIGNED_KINDS:
        raise SceneError(f"{label}: vlab design plans extension tests (gauge length, extensometer strain range); "
                         f"test.kind = {scene.test.kind!r} is fitted by vlab fit but not designed")


def _candidate(fe: dict, path: Path | None, gauge: float | None):
    """(fe dict of the candidate: the fit's card and volumetric energy on the candidate's specimen,
    mesh and test; its SpecimenTest without a range)."""
    from vlab.loading.kinds import kind_of
    from vlab.pipeline.prepare import build_specimen
    from vlab.scene import parse_scene

    if path is None:
        path, raw, scene = Path(fe["scene_path"]), fe["scene_raw"], fe["scene"]
        label = "fe.scene"
    else:
        label = f"--specimens {path.name}"
        path, raw, scene = load_scene(path.resolve(), label)
        check_scene(scene, fe["model"], label)
        check_designable(scene, label)
    if gauge is not None:
        raw = _with_gauge(raw, scene.specimen.shape, gauge)
        try:
            scene = parse_scene(raw, path.name, path.parent)
        except SceneError as exc:
            raise SceneError(f"--gauge-lengths {gauge:g} on {label}: {exc}") from None
    length = build_specimen(scene).extensometers[0].length
    if gauge is not None and abs(length - gauge) > 1e-9 * gauge:
        raise SceneError(f"--gauge-lengths {gauge:g}: the {scene.specimen.shape} of {label} places its "
                         f"extensometer marks {length:g} mm apart whatever the gauge length asked")
    # the fit's own scene keeps the axes its data read (a cruciform may be read on x only)
    own = path == Path(fe["scene_path"])
    axes = tuple(fe["axes"]) if own else tuple(kind_of(scene.test).axes)
    cand = fe | {"scene_path": str(path), "scene_raw": raw, "scene": scene, "axes": axes,
                 "channels": fe.get("channels") if own else None}  # another scene's: a load cell per axis
    return cand, SpecimenTest(str(path), path.stem, scene.test.kind, scene.specimen.shape, float(length), 0.0, 0.0)


def specimen_candidates(fe: dict, specimens, gauges) -> list:
    """(fe dict, SpecimenTest) of each scene (the fit's own, then ``specimens``) at each gauge
    length (the scene's own, then ``gauges``): validated and meshed, not run (SceneError first)."""
    return [_candidate(fe, path, gauge) for path in [None, *specimens] for gauge in [None, *gauges]]


def specimen_runs(candidates, values: dict, lo: float, hi: float, points: int) -> list[SpecimenRun]:
    """Each candidate run at the full constants ``values`` (fixed ones included), its readings
    planned at ``points`` strains over [lo, hi]."""
    out = []
    for cand, test in candidates:
        t0 = time.perf_counter()
        try:
            sim = simulate(cand, values)
        except RuntimeError as exc:
            raise SceneError(f"{test.name}: {exc}") from None
        out.append(SpecimenRun(dataclasses.replace(test, lo=lo, hi=hi, points=points), sim,
                               time.perf_counter() - t0))
    return out


def specimen_rows(sim, test: SpecimenTest, relative: bool, s: float = 1.0, elongation_sd: float = 0.0) -> np.ndarray:
    """J_t = ∂r/∂p of the readings at ``test``'s strains, per unit scatter (n × n_p, or 2n × n_p);
    with an extensometer scatter (``elongation_sd`` mm) weighted as ``strain_noise_weights``."""
    e = np.linspace(test.lo, test.hi, test.points)
    b = None
    if sim.strain.shape[1] == 2:  # a cruciform: the y extensometer read at the same instants
        b = CubicSpline(np.r_[0.0, sim.strain[:, 0]], np.r_[0.0, sim.strain[:, 1]])(e)
    d = Dataset(test.label, test.scene, "specimen", "fit", 1.0, "nominal", e, b,
                np.ones(len(e) * (1 if b is None else 2)))
    _, _, predicted = residuals(sim, d, False)
    d = dataclasses.replace(d, y=predicted)
    _, J, _ = residuals(sim, d, relative)
    strain_sd = elongation_sd / test.gauge_length if elongation_sd else 0.0
    return J * strain_noise_weights(sim, d, relative, s, strain_sd)[:, None]


def strain_noise_weights(sim, d, relative: bool, s: float, strain_sd: float) -> np.ndarray:
    """Effective-variance weights of readings whose strain also scatters (sd ``strain_sd`` = the
    extensometer's elongation sd / its gauge length): a strain error δe moves the residual by
    √weight F'(e) δe / scale, so each reading's variance is s² + weight (F'(e_i) strain_sd / scale_i)² and its
    row of J is weighted by w_i = s / √(that), F' = dF/de of the force spline (N per unit strain),
    scale_i as the residual's (max(|F_i|, 0.01 max|F|) per axis, relative; 1, absolute)."""
    if strain_sd == 0.0:
        return np.ones(len(d.y))
    parts, n = [(0, d.a)] + ([(1, d.b)] if d.b is not None else []), d.points
    slope, scale = [], []
    for a, e in parts:
        slope.append(CubicSpline(np.r_[0.0, sim.strain[:, a]], np.r_[0.0, sim.force[:, a]])(e, 1))
        y = np.abs(d.y[a * n:(a + 1) * n])
        scale.append(np.maximum(y, 0.01 * np.max(y)) if relative else np.ones_like(y))
    moved = np.sqrt(d.weight) * np.concatenate(slope) * strain_sd / np.concatenate(scale)
    return s / np.sqrt(s * s + moved ** 2)


def data_rows(spec, own: SpecimenRun, s: float = 1.0, elongation_sd: float = 0.0) -> np.ndarray:
    """∂r/∂p of the fit file's own specimen readings, from ``own`` (fe.scene at its own gauge
    length, run at the design's constants), weighted for an extensometer scatter as
    ``strain_noise_weights``."""
    sim, gauge_length = own.sim, own.test.gauge_length
    relative = spec.residual == "relative"
    sets = [d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"]
    strain_sd = elongation_sd / gauge_length if elongation_sd else 0.0
    return np.vstack([residuals(sim, d, relative)[1] * strain_noise_weights(sim, d, relative, s, strain_sd)[:, None]
                      for d in sets])


def strain_range(spec) -> tuple[float, float]:
    """The extensometer strain range (axis x) of the fit file's specimen readings."""
    sets = [d for d in spec.datasets if d.kind == "specimen" and d.role == "fit"]
    return min(float(np.min(d.a)) for d in sets), max(float(np.max(d.a)) for d in sets)
