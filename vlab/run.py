"""The one place that sequences a test: scene → specimen mesh → solve → measure → result.

Nothing here computes physics or draws: it wires the layers together, times them, and packs what
they produced into a RunResult that the writers and reports consume.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from vlab import __version__
from vlab.fe.assembly import Partition
from vlab.fe.newton import NewtonOptions
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.fe.stepping import Failure, SolveHistory, Stepping, run_schedule
from vlab.geometry.block import block_specimen
from vlab.geometry.specimen import Specimen
from vlab.loading.grips import grip_loading
from vlab.loading.schedule import monotonic_schedule
from vlab.materials import make_material
from vlab.measure.elastic_constants import ElasticConstants, elastic_constants
from vlab.measure.recorder import Curve, Recorder
from vlab.measure.reference import homogeneous_curve, relative_error
from vlab.scene import Scene


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
    raise ValueError(f"specimen.shape {spec.shape!r} is not supported by this build")


def run_scene(scene: Scene, on_level=None) -> RunResult:
    """Run the test a scene describes; never raises for solver trouble (see history.failure)."""
    clock = time.perf_counter
    timing: dict[str, float] = {}
    t0 = clock()
    specimen = build_specimen(scene)
    space = DisplacementSpace.build(specimen.mesh, scene.mesh.order)
    material = make_material(scene.material.model, scene.material.moduli.lmbda, scene.material.moduli.mu)
    body = HyperelasticBody(space, material)
    loading = grip_loading(specimen, space.node_coordinates, scene.test.stretch, scene.test.grips)
    partition = Partition.build(body.pattern, loading.prescribed)
    timing["mesh_s"] = clock() - t0

    recorder = Recorder(space, specimen, scene.test.stretch, loading.moving_dofs)
    measure_time = [0.0]

    def observe(level):
        t = clock()
        recorder(level)
        measure_time[0] += clock() - t
        if on_level is not None:
            on_level(level)

    stepping = Stepping(
        schedule=monotonic_schedule(scene.test.stretch, scene.test.steps, scene.measure.modulus_window,
                                    scene.measure.modulus_points),
        max_cutbacks=scene.solver.max_cutbacks,
        newton=NewtonOptions(rtol=scene.solver.rtol, max_iterations=scene.solver.max_iterations),
    )
    force_floor = 1e-12 * material.mu * specimen.length_scale**2
    t1 = clock()
    history = run_schedule(body, partition, loading.u_hat, stepping,
                           (force_floor, specimen.length_scale), observe)
    timing["measure_s"] = measure_time[0]
    timing["solve_s"] = clock() - t1 - measure_time[0]

    t2 = clock()
    curve = recorder.curve
    constants = elastic_constants(curve, scene.measure.modulus_window, scene.measure.fit)
    reference = None
    if specimen.shape == "block" and scene.test.grips == "roller":
        reference = homogeneous_curve(material, curve.stretch)
        for axis in curve.axes:
            key = f"stress_{'xy'[axis]}"
            reference[f"max_relative_error_{'xy'[axis]}"] = relative_error(
                curve.column("stress", axis), reference[key])
    timing["measure_s"] += clock() - t2
    timing["total_s"] = clock() - t0
    return RunResult(scene, specimen, space, curve, constants, history, timing, reference)


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


def observed_order(residuals: list[float], floor: float = 1e-13) -> float | None:
    """Convergence order p from the last three residuals above round-off: r₊ ≈ C r^p."""
    r = [x for x in residuals if x > floor]
    if len(r) < 3 or r[-2] == r[-3]:
        return None
    return float(np.log(r[-1] / r[-2]) / np.log(r[-2] / r[-3]))


def vlab_version() -> str:
    return __version__
