"""The one place that sequences a test: scene → specimen mesh → solve → measure → result.

Nothing here computes physics or draws: it wires the layers together, times them, and packs what
they produced into a RunResult that the writers and reports consume.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass, field

import numpy as np

from vlab import jit
from vlab.fe.assembly import Partition
from vlab.fe.iterative import choose as choose_linear
from vlab.fe.linsolve import solver_in_use
from vlab.fe.newton import CHORD_CONTRACTION, NewtonOptions
from vlab.fe.mixed import MixedHyperelasticBody
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.fe.spring_network import SpringNetwork
from vlab.fe.stepping import Failure, SolveHistory, Stepping, run_schedule
from vlab.fe.timers import phase_clock
from vlab.geometry.block import block_specimen
from vlab.geometry.cruciform import cruciform_specimen
from vlab.geometry.imported import imported_specimen
from vlab.geometry.dogbone import dogbone_specimen
from vlab.geometry.sheet import sheet_specimen
from vlab.geometry.quality import MeshQuality, mesh_quality
from vlab.geometry.mesh_check import MeshError, check_mesh
from vlab.geometry.specimen import Specimen
from vlab.loading.grips import grip_loading
from vlab.loading.protocol import protocol_levels
from vlab.materials import make_material
from vlab.materials.history import HistoryMaterial
from vlab.materials.plane import plane_model
from vlab.materials.split import SPLIT_LAWS, make_split_law
from vlab.measure.centre_stress import CentreStressProbe, centre_report
from vlab.measure.elastic_constants import (ElasticConstants, crosshead_modulus, elastic_constants,
                                            first_loading)
from vlab.measure.homogeneity import HomogeneityProbe
from vlab.measure.recorder import Curve, Recorder
from vlab.measure.reference import homogeneous_curve, relative_error
from vlab.moduli import MIXED_NU_LIMIT
from vlab.scene import SPRING_NETWORK, Scene, SceneError
from vlab.report.results import failure_dict, observed_order  # noqa: F401  (moved there; kept importable here)


class MeshQualityError(SceneError):
    """The mesh's worst element is below the scene's ``mesh.min_quality``."""

log = logging.getLogger(__name__)
LOCKING_NU = 0.45  # above this, displacement-only elements lock on non-uniform fields
from vlab.checks.admissibility import inadmissible_request
from vlab.loading.restraint import under_constrained_message, unrestrained_modes
from vlab.checks.buckling import lateral_deflection
from vlab.checks.imperfection import imperfect_specimen
from vlab.checks.monitor import MonitorOptions, StabilityMonitor


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
    mesh = scene.mesh
    if spec.shape == "block":
        return block_specimen(spec.size, mesh.size, mesh.cell, scene.measure.gauge_length, mesh.symmetry)
    if spec.shape == "dogbone":
        return dogbone_specimen(spec.dimensions, mesh.size, mesh.cell, mesh.gauge_size, mesh.symmetry, mesh.mesher)
    if spec.shape == "sheet":
        return sheet_specimen(spec.size, spec.thickness, mesh.size, mesh.cell, scene.measure.gauge_length)
    if spec.shape == "cruciform":
        return cruciform_specimen(spec.dimensions, mesh.size, mesh.cell, mesh.gauge_size, mesh.symmetry,
                                  scene.measure.gauge_length)
    if spec.shape in ("mesh", "cad"):  # a mesh file, or Gmsh's mesh of a CAD file
        return imported_specimen(spec.spec, spec.data)
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
    """The body a scene's material.model and mesh.formulation ask for: a continuum material
    (displacement-only or mixed θ/p condensed per element), on a 2D space (a sheet) the
    material's plane-stress or plane-strain reduction, or the spring network."""
    moduli = scene.material.moduli
    if scene.material.model == SPRING_NETWORK:
        return SpringNetwork(space, moduli.E)
    if scene.mesh.formulation == "mixed":
        return MixedHyperelasticBody(space, make_split_law(scene.material.model, moduli.lmbda, moduli.mu))
    elastic = make_material(scene.material.model, moduli.lmbda, moduli.mu)
    if space.dim == 2:
        elastic = plane_model(elastic, scene.specimen.plane)
    if not scene.effects:  # the elastic path: nothing else is built or assembled
        return HyperelasticBody(space, elastic)
    from vlab.effects.build import external_load, history_law
    from vlab.fe.external_load import LoadedBody
    from vlab.fe.history_body import HistoryBody
    law = history_law(scene, elastic)
    body = HistoryBody(space, law) if law is not None else HyperelasticBody(space, elastic)
    f_ext = external_load(scene, space)
    return body if f_ext is None else LoadedBody(body, f_ext)


def run_scene(scene: Scene, on_level=None, specimen: Specimen | None = None) -> RunResult:
    """Run the test a scene describes; never raises for solver trouble (see history.failure).

    ``specimen`` replaces the one the scene would build (same shape; e.g. a perturbed mesh).
    Raises MeshQualityError (a SceneError) before solving if the mesh is below mesh.min_quality.
    ``timing`` splits the wall time: mesh_s, solve_s (of which assembly_s and linear_solve_s,
    factorizations + back-substitutions, exclusive of each other) and measure_s."""
    jit.available()  # numba's one-time start-up (~0.3 s), before the clocks: no import starts it
    with phase_clock() as phases:
        result = _run_scene(scene, on_level, specimen)
    result.timing |= {"assembly_s": 0.0, "linear_solve_s": 0.0} | phases.as_timing()
    return result


def _run_scene(scene: Scene, on_level, specimen: Specimen | None) -> RunResult:
    clock = time.perf_counter
    timing: dict[str, float] = {}
    t0 = clock()
    seeded = None
    if scene.test.imperfection is not None:
        seeded = _seeded_specimen(scene, specimen or build_specimen(scene))
        if seeded.specimen is None:  # no buckling mode to seed: the first pass is the answer
            seeded.first_pass.extra["warnings"].append(seeded.note)
            return seeded.first_pass
        specimen = seeded.specimen
    specimen = specimen or build_specimen(scene)
    quality = checked_quality(scene, specimen)
    space = DisplacementSpace.build(specimen.mesh, scene.mesh.order, specimen.sheet_thickness or 1.0)
    body = make_body(scene, space)
    material = getattr(body, "material", None)  # None for the spring network: no analytic oracle
    ground = getattr(material, "elastic", material)  # a history law's elastic ground law
    if isinstance(material, HistoryMaterial) or scene.effect("gravity") is not None:
        material = None  # a history law or a dead load: the elastic homogeneous oracles do not apply
    loading = grip_loading(specimen, space.node_coordinates, scene.test.stretch, scene.test.grips)
    partition = Partition.build(body.pattern, loading.prescribed)
    timing["mesh_s"] = clock() - t0

    recorder = Recorder(space, specimen, scene.test.stretch, loading.moving_dofs, material,
                        CentreStressProbe.build(space, specimen, material))
    probe = HomogeneityProbe.build(space, specimen, material) if material is not None else None
    homogeneity: list[dict] = []
    measure_time = [0.0]

    monitor = StabilityMonitor(body, partition, loading.moving_dofs, scene.test.stretch,
                               _law_label(scene), loading.u_hat,
                               MonitorOptions(eigenvalues=scene.solver.eigenvalues,
                                              limit_points=_watch_limit_points(scene)))
    deflection: list[float] = []

    def observe(level):
        monitor(level)
        deflection.append(lateral_deflection(space.node_coordinates, level.evaluation.u))
        t = clock()
        recorder(level)
        if hasattr(body, "keep_cells"):
            body.keep_cells(level.evaluation)
        if probe is not None:
            homogeneity.append(probe.read(level.evaluation.F, recorder.curve.force[0][-1]))
        measure_time[0] += clock() - t
        if on_level is not None:
            on_level(level)

    levels = protocol_levels(scene.test.protocol, scene.test.stretch, scene.test.steps,
                             scene.measure.modulus_window, scene.measure.modulus_points)
    linear_solver = choose_linear(scene.solver.linear, len(partition.free), solver_in_use())
    stepping = Stepping(
        schedule=levels.t, times=levels.time,
        force_held=levels.force_held if levels.force_held.any() else None,
        force_targets=levels.force,
        max_cutbacks=scene.solver.max_cutbacks,
        newton=NewtonOptions(rtol=scene.solver.rtol, max_iterations=scene.solver.max_iterations,
                             linear=linear_solver,
                             chord_contraction=CHORD_CONTRACTION if scene.solver.newton == "reuse" else 0.0),
        accept=monitor.accept,
        tangents=monitor.tangents,  # the stability check's factorization feeds the next predictor
    )
    # Newton's residual is relative to the grip reaction; at a stress-free state reached again
    # (unloading to stretch 1) the reaction vanishes, so it is floored at the force of a 1e-6
    # strain: absolute tolerance rtol·1e-6·μL², still far above the round-off of f_int (~1e-16·μL²)
    force_floor = 1e-6 * scene.material.moduli.mu * specimen.length_scale**2
    t1 = clock()
    refusal = _refusal(ground, scene, space, loading.prescribed)
    if refusal is not None:
        history = SolveHistory(failure=Failure(0, 1.0, 1.0, 0.0, refusal, []))
    else:
        history = run_schedule(body, partition, loading.u_hat, stepping,
                               (force_floor, specimen.length_scale), observe)
    timing["measure_s"] = measure_time[0]
    timing["solve_s"] = clock() - t1 - measure_time[0]

    t2 = clock()
    curve = recorder.curve
    fitted = first_loading(curve) if scene.test.protocol.unloads else curve
    constants = elastic_constants(fitted, scene.measure.modulus_window, scene.measure.fit)
    uncertainty = None
    if scene.effect("noise") is not None:  # the instruments' readings replace the exact ones
        from vlab.measure.noise import measure_with_noise
        curve, constants, uncertainty = measure_with_noise(scene.effect("noise"), curve, specimen, scene.measure)
    reference = None
    if material is not None and specimen.shape in ("block", "sheet") and scene.test.grips == "roller":
        reference = homogeneous_curve(material, curve.stretch)
        for axis in curve.axes:
            key = f"stress_{'xy'[axis]}"
            reference[f"max_relative_error_{'xy'[axis]}"] = relative_error(
                curve.column("stress", axis), reference[key])
    extra = {"mesh_quality": quality.as_dict(),
             "crosshead": crosshead_modulus(first_loading(curve) if scene.test.protocol.unloads else curve,
                                            scene.measure.modulus_window, scene.measure.fit)}
    if uncertainty is not None:
        extra["uncertainty"] = uncertainty
    centre = centre_report(curve, scene.measure.modulus_window, scene.measure.fit)
    if centre is not None:
        extra["cruciform"] = centre
    if homogeneity:
        extra["homogeneity"] = _homogeneity_report(curve, homogeneity, scene.measure.modulus_window)
    timing["measure_s"] += clock() - t2
    timing["total_s"] = clock() - t0
    extra["linear_solver"] = {"requested": scene.solver.linear, "newton": linear_solver,
                              "direct": solver_in_use()}
    extra["tangent_kernel"] = getattr(body, "tangent_kernel", "numpy")
    extra |= {"body": body, "partition": partition, "stability": [r.as_dict() for r in monitor.records], "warnings": _warnings(scene)}
    extra |= _buckling_extra(monitor, deflection, seeded)
    if scene.effects or scene.test.protocol.name != "monotonic":
        from vlab.effects.report import effects_summary
        extra["effects"] = effects_summary(scene, body, history.levels)
    return RunResult(scene, specimen, space, curve, constants, history, timing, reference, extra)


@dataclass
class _Seeded:
    """The first (perfect) pass of an imperfect test and the specimen it seeds (None: no mode)."""

    first_pass: "RunResult"
    specimen: Specimen | None
    note: str = ""


def _seeded_specimen(scene: Scene, specimen: Specimen) -> _Seeded:
    """Run the perfect specimen to its first loss of stability; seed its mode as imperfection."""
    perfect = dataclasses.replace(scene, test=dataclasses.replace(scene.test, imperfection=None))
    first = run_scene(perfect, specimen=specimen)
    critical = first.extra.get("critical_state")
    if critical is None or not critical.is_buckling:
        return _Seeded(first, None, "test.imperfection: the perfect specimen did not buckle up to the "
                                    "requested stretch, so there is no mode to seed; this is the perfect run")
    space = first.space
    moved = imperfect_specimen(specimen, space, critical.mode,
                               scene.test.imperfection * specimen_thickness(scene))
    return _Seeded(first, moved)


def specimen_thickness(scene: Scene) -> float:
    """The smallest cross-section dimension (mm), the scale of a buckling imperfection."""
    spec = scene.specimen
    if spec.shape == "block":
        return float(min(spec.size[1], spec.size[2]))
    return float(min(spec.dimensions.thickness, spec.dimensions.width))


def _buckling_extra(monitor: StabilityMonitor, deflection: list[float], seeded: "_Seeded | None") -> dict:
    """The critical state (results.json → critical), its mode (not serialized), the centre-line
    deflection per level, and for an imperfect test the perfect pass's critical state."""
    out: dict = {"lateral_deflection": deflection}
    if monitor.critical is not None:
        out |= {"critical": monitor.critical.as_dict(), "critical_state": monitor.critical}
    if seeded is not None:
        out["imperfection"] = {"perfect_critical": seeded.first_pass.extra.get("critical"),
                               "mode": seeded.first_pass.extra["critical_state"].mode}
    return out


def _watch_limit_points(scene: Scene) -> bool:
    """A falling force is a limit point only on a monotonic ramp of an elastic material, and not
    on a deliberately imperfect (post-buckled) path: unloading, relaxing, creeping and a bent
    strip's softening are the physics asked for. Instrument noise changes no physics."""
    from vlab.effects import EFFECTS

    physical = [e for e in scene.effects if EFFECTS[e.name].role != "measure"]
    return scene.test.protocol.name == "monotonic" and not physical and scene.test.imperfection is None


def _law_label(scene: Scene) -> str:
    """The law a stability diagnosis names: the model, or the history law wrapping it."""
    from vlab.effects import EFFECTS

    law = next((e.name for e in scene.effects if EFFECTS[e.name].role == "material"), None)
    return scene.material.model if law is None else f"{scene.material.model} with effects.{law}"


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
    if scene.effects or scene.test.protocol.name != "monotonic":
        from vlab.effects.build import effect_warnings
        found += effect_warnings(scene)
    if nu > LOCKING_NU and scene.mesh.formulation == "displacement":
        cure = (f'use mesh.formulation = "mixed" (locking-free up to nu = {MIXED_NU_LIMIT:g})'
                if scene.material.model in SPLIT_LAWS else
                f'mesh.formulation = "mixed" would cure it but needs material.model in '
                f'{", ".join(SPLIT_LAWS)}')
        found.append(f"material.nu = {nu:g} > {LOCKING_NU:g} with the displacement-only formulation: "
                     "expect volumetric locking (too stiff) wherever the field is not uniform, e.g. "
                     f"with clamped grips; homogeneous roller tests are unaffected; {cure}")
    for text in found:
        log.warning(text)
    return found


def _refusal(material, scene: Scene, space: DisplacementSpace, prescribed) -> str | None:
    """Why the request cannot be solved at all (rigid-body modes, no admissible state), or None."""
    modes = unrestrained_modes(space.node_coordinates, prescribed)
    if modes:
        return under_constrained_message(modes)
    return inadmissible_request(material, scene.test.stretch)
