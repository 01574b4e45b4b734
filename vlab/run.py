"""The one place that sequences a test: scene → specimen mesh → solve → measure → result.

Nothing here computes physics or draws: it wires the layers together, times them, and packs what
they produced into a RunResult that the writers and reports consume.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from vlab import __version__
from vlab.fe.assembly import Partition
from vlab.fe.iterative import choose as choose_linear
from vlab.fe.linsolve import solver_in_use
from vlab.fe.newton import NewtonOptions
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.fe.spring_network import SpringNetwork
from vlab.fe.stepping import Failure, SolveHistory, Stepping, run_schedule
from vlab.geometry.block import block_specimen
from vlab.geometry.dogbone import dogbone_specimen
from vlab.geometry.quality import MeshQuality, mesh_quality
from vlab.geometry.mesh_check import MeshError, check_mesh
from vlab.geometry.specimen import Specimen
from vlab.loading.grips import grip_loading
from vlab.loading.schedule import monotonic_schedule
from vlab.materials import make_material
from vlab.measure.elastic_constants import ElasticConstants, crosshead_modulus, elastic_constants
from vlab.measure.homogeneity import HomogeneityProbe
from vlab.measure.recorder import Curve, Recorder
from vlab.measure.reference import homogeneous_curve, relative_error
from vlab.scene import SPRING_NETWORK, Scene, SceneError


class MeshQualityError(SceneError):
    """The mesh's worst element is below the scene's ``mesh.min_quality``."""

log = logging.getLogger(__name__)
LOCKING_NU = 0.45  # above this, displacement-only elements lock on non-uniform fields
from vlab.stability.admissibility import inadmissible_request
from vlab.stability.constraints import under_constrained_message, unrestrained_modes
from vlab.stability.monitor import StabilityMonitor


@dataclass
class RunResult:
    scene: Scene
    specimen: Specimen
    space: DisplacementSpace
    curve: Curve
    constants: ElasticConstants
    history: SolveHistory
    timing: dict[str, float]
    reference: dict | None = None
    extra: dict = field(default_factory=dict)

    @property
    def converged(self) -> bool:
        return self.history.failure is None

    @property
    def final_displacement(self) -> np.ndarray:
        levels = self.history.levels
        return levels[-1].evaluation.u if levels else np.zeros(self.space.n_dofs)


def build_specimen(scene: Scene) -> Specimen:
    spec = scene.specimen
    if spec.shape == "block":
        return block_specimen(spec.size, scene.mesh.size, scene.mesh.cell, scene.measure.gauge_length)
    if spec.shape == "dogbone":
        return dogbone_specimen(spec.dimensions, scene.mesh.size, scene.mesh.cell, scene.mesh.gauge_size)
    raise ValueError(f"specimen.shape {spec.shape!r} is not supported by this build")


def checked_quality(scene: Scene, specimen: Specimen) -> MeshQuality:
    """The mesh's quality; MeshQualityError if the mesh is invalid (inverted or flat elements,
    duplicate or unused nodes) or its worst element is below mesh.min_quality."""
    try:
        check_mesh(specimen.mesh)
    except MeshError as exc:
        raise MeshQualityError(f"invalid mesh: {exc}") from None
    quality = mesh_quality(specimen.mesh)
    if quality.min_quality < scene.mesh.min_quality:
        raise MeshQualityError(
            f"mesh.min_quality: the {specimen.shape} mesh's worst element (#{quality.worst_element}) has "
            f"{quality.measure} quality {quality.min_quality:.3g} < mesh.min_quality = "
            f"{scene.mesh.min_quality:g} (1 is ideal; max aspect ratio {quality.max_aspect_ratio:.3g}); "
            f"change mesh.size / mesh.cell, or lower mesh.min_quality")
    return quality


def make_body(scene: Scene, space: DisplacementSpace):
    """The body a scene's material.model asks for: a continuum material or the spring network."""
    moduli = scene.material.moduli
    if scene.material.model == SPRING_NETWORK:
        return SpringNetwork(space, moduli.E)
    return HyperelasticBody(space, make_material(scene.material.model, moduli.lmbda, moduli.mu))


def run_scene(scene: Scene, on_level=None, specimen: Specimen | None = None) -> RunResult:
    """Run the test a scene describes; never raises for solver trouble (see history.failure).

    ``specimen`` replaces the one the scene would build (same shape; e.g. a perturbed mesh).
    Raises MeshQualityError (a SceneError) before solving if the mesh is below mesh.min_quality."""
    clock = time.perf_counter
    timing: dict[str, float] = {}
    t0 = clock()
    specimen = specimen or build_specimen(scene)
    quality = checked_quality(scene, specimen)
    space = DisplacementSpace.build(specimen.mesh, scene.mesh.order)
    body = make_body(scene, space)
    material = getattr(body, "material", None)  # None for the spring network: no analytic oracle
    loading = grip_loading(specimen, space.node_coordinates, scene.test.stretch, scene.test.grips)
    partition = Partition.build(body.pattern, loading.prescribed)
    timing["mesh_s"] = clock() - t0

    recorder = Recorder(space, specimen, scene.test.stretch, loading.moving_dofs)
    probe = HomogeneityProbe.build(space, specimen, material) if material is not None else None
    homogeneity: list[dict] = []
    measure_time = [0.0]

    monitor = StabilityMonitor(body, partition, loading.moving_dofs, scene.test.stretch,
                               scene.material.model, loading.u_hat)

    def observe(level):
        monitor(level)
        t = clock()
        recorder(level)
        if probe is not None:
            homogeneity.append(probe.read(level.evaluation.F, recorder.curve.force[0][-1]))
        measure_time[0] += clock() - t
        if on_level is not None:
            on_level(level)

    linear_solver = choose_linear(scene.solver.linear, len(partition.free), solver_in_use())
    stepping = Stepping(
        schedule=monotonic_schedule(scene.test.stretch, scene.test.steps, scene.measure.modulus_window,
                                    scene.measure.modulus_points),
        max_cutbacks=scene.solver.max_cutbacks,
        newton=NewtonOptions(rtol=scene.solver.rtol, max_iterations=scene.solver.max_iterations,
                             linear=linear_solver),
        accept=monitor.accept,
        tangents=monitor.tangents,  # the stability check's factorization feeds the next predictor
    )
    force_floor = 1e-12 * scene.material.moduli.mu * specimen.length_scale**2
    t1 = clock()
    refusal = _refusal(material, scene, space, loading.prescribed)
    if refusal is not None:
        history = SolveHistory(failure=Failure(0, 1.0, 1.0, 0.0, refusal, []))
    else:
        history = run_schedule(body, partition, loading.u_hat, stepping,
                               (force_floor, specimen.length_scale), observe)
    timing["measure_s"] = measure_time[0]
    timing["solve_s"] = clock() - t1 - measure_time[0]

    t2 = clock()
    curve = recorder.curve
    constants = elastic_constants(curve, scene.measure.modulus_window, scene.measure.fit)
    reference = None
    if material is not None and specimen.shape == "block" and scene.test.grips == "roller":
        reference = homogeneous_curve(material, curve.stretch)
        for axis in curve.axes:
            key = f"stress_{'xy'[axis]}"
            reference[f"max_relative_error_{'xy'[axis]}"] = relative_error(
                curve.column("stress", axis), reference[key])
    extra = {"mesh_quality": quality.as_dict(),
             "crosshead": crosshead_modulus(curve, scene.measure.modulus_window, scene.measure.fit)}
    if homogeneity:
        extra["homogeneity"] = _homogeneity_report(curve, homogeneity, scene.measure.modulus_window)
    timing["measure_s"] += clock() - t2
    timing["total_s"] = clock() - t0
    extra["linear_solver"] = {"requested": scene.solver.linear, "newton": linear_solver,
                              "direct": solver_in_use()}
    extra |= {"body": body, "stability": [r.as_dict() for r in monitor.records], "warnings": _warnings(scene)}
    return RunResult(scene, specimen, space, curve, constants, history, timing, reference, extra)


def _homogeneity_report(curve: Curve, rows: list[dict], window: tuple[float, float]) -> dict:
    """The gauge-section statistics at small strain (last level with extensometer strain within
    the modulus window; the elastic state) and at the final level."""
    strain = np.abs(np.array(curve.strain[0]))
    small = np.flatnonzero(strain <= window[1] * (1 + 1e-9))
    out = {"final": rows[-1] | {"extensometer_strain": curve.strain[0][-1]}}
    if len(small):
        i = int(small[-1])
        out["small_strain"] = rows[i] | {"extensometer_strain": curve.strain[0][i]}
    return out


def _warnings(scene: Scene) -> list[str]:
    """Caveats about the set-up (also logged)."""
    found = []
    nu = scene.material.moduli.nu
    if nu > LOCKING_NU:
        found.append(f"material.nu = {nu:g} > {LOCKING_NU:g} with the displacement-only formulation: "
                     "expect volumetric locking (too stiff) wherever the field is not uniform, e.g. "
                     "with clamped grips; homogeneous roller tests are unaffected")
    for text in found:
        log.warning(text)
    return found


def _refusal(material, scene: Scene, space: DisplacementSpace, prescribed) -> str | None:
    """Why the request cannot be solved at all (rigid-body modes, no admissible state), or None."""
    modes = unrestrained_modes(space.node_coordinates, prescribed)
    if modes:
        return under_constrained_message(modes)
    return inadmissible_request(material, scene.test.stretch)


def stretch_at(scene: Scene, t: float) -> list[float]:
    return [1.0 + t * (s - 1.0) for s in scene.test.stretch]


def failure_dict(scene: Scene, failure: Failure) -> dict:
    return {
        "step": failure.level,
        "stretch": stretch_at(scene, failure.t_attempted),
        "target_stretch": stretch_at(scene, failure.t_target),
        "last_converged_stretch": stretch_at(scene, failure.t_converged),
        "reason": failure.reason,
        "residual_history": failure.residuals,
        "min_J": failure.min_J,
        "element": failure.element,
        "quadrature_point": failure.quadrature_point,
    }


def observed_order(residuals: list[float], floor: float = 1e-10) -> float | None:
    """Convergence order p from the last three relative residuals above ``floor``: r₊ ≈ C r^p.

    Relative residuals below ~1e-10 are dominated by round-off in the force sums, so they say
    nothing about the order; None when fewer than three iterates lie above the floor."""
    r = [x for x in residuals if x > floor]
    if len(r) < 3 or r[-2] == r[-3]:
        return None
    return float(np.log(r[-1] / r[-2]) / np.log(r[-2] / r[-3]))


def vlab_version() -> str:
    return __version__
