"""The one place that sequences a test: scene → prepare (mesh, body, grips) → solve (load
stepping, observers) → measure → RunResult.

Nothing here computes physics or draws: it wires the stages of vlab.pipeline together, times
them, and packs what they produced into a RunResult (vlab.pipeline.result) that the writers and
reports consume: typed Diagnostics for results.json, the live solver objects apart.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass

from vlab import jit
from vlab.checks.buckling import lateral_deflection
from vlab.checks.imperfection import imperfect_specimen
from vlab.checks.locking import LOCKING_NU, locking_free, locking_prone, uniform_field  # noqa: F401  (uniform_field: importable here)
from vlab.checks.monitor import StabilityMonitor
from vlab.fe.linsolve import solver_in_use
from vlab.fe.stepping import Level
from vlab.fe.timers import memory_phase, phase_clock
from vlab.geometry.shapes import SHAPES
from vlab.geometry.specimen import Specimen
from vlab.materials import MODELS
from vlab.moduli import MIXED_NU_LIMIT
from vlab.pipeline.dic import check_view, with_dic
from vlab.pipeline.measure import Instruments, Measured, measure
from vlab.pipeline.prepare import MeshQualityError, Prepared, build_specimen, checked_quality, make_body, prepare
from vlab.pipeline.result import Diagnostics, RunResult, SolverObjects
from vlab.pipeline.solve import Observer, Solved, solve, stability_monitor
from vlab.report.results import failure_dict, observed_order  # noqa: F401  (moved there; kept importable here)
from vlab.scene import Scene
from vlab.settings import Settings, current, using

__all__ = ["RunResult", "Diagnostics", "SolverObjects", "MeshQualityError", "run_scene", "build_specimen",
           "checked_quality", "make_body", "specimen_thickness"]

log = logging.getLogger(__name__)


def run_scene(scene: Scene, on_level=None, specimen: Specimen | None = None,
              settings: Settings | None = None, observe=None) -> RunResult:
    """Run the test a scene describes; never raises for solver trouble (see history.failure).

    ``specimen`` replaces the one the scene would build (same shape; e.g. a perturbed mesh).
    Raises MeshQualityError (a SceneError) before solving if the mesh is below mesh.min_quality.
    ``timing`` splits the wall time: mesh_s, solve_s (of which assembly_s and linear_solve_s,
    factorizations + back-substitutions, exclusive of each other) and measure_s. ``settings``
    (kernel, assembly threads, direct solver; vlab.settings) apply for this run only; None: the
    process's installed ones. ``observe(prepared, tangents)`` -> an observer called with every
    converged level after the stability monitor vetted it, when ``tangents`` (the monitor's
    TangentCache) holds the factorized tangent at that state (vlab.identify.fe_levels uses it)."""
    with using(settings):
        return _timed_run(scene, on_level, specimen, observe)


def _timed_run(scene: Scene, on_level, specimen: Specimen | None, observe=None) -> RunResult:
    jit.available(current())  # numba's one-time start-up (~0.3 s), before the clocks: no import starts it
    with phase_clock() as phases:
        result = _run_scene(scene, on_level, specimen, observe)
        result = _locking_checked(result, on_level, specimen, observe)
    result = with_dic(result)  # [instruments.dic]: the camera and its DIC (nothing without the table)
    result.timing |= {"assembly_s": 0.0, "linear_solve_s": 0.0} | phases.as_timing()
    result.timing["peak_memory_mb"] = phases.peak_memory_mb  # per phase (vlab.fe.timers)
    return result


def _locking_checked(result: RunResult, on_level, specimen: Specimen | None, observe=None) -> RunResult:
    """A stop the locking displacement-only elements cannot vouch for (CriticalState.suspect), run
    again with mesh.formulation = "mixed" on the same mesh when the user left the formulation at
    its default: the mixed run is the answer (it reaches the stretch, or its own stop is the true
    one), with a warning that says what the displacement-only run found; else the first run. Not
    under an ``observe`` factory (FE-in-the-loop sensitivities): its observers belong to the first
    run's body, so that run's stop, whose message names the cure, stands."""
    critical = result.solver.critical_state
    mixed = locking_free(result.scene) if critical is not None and critical.suspect else None
    if mixed is None or observe is not None:
        return result
    second = _run_scene(mixed, on_level, specimen, observe)
    # the wall time the answer cost includes the displacement-only run that raised the doubt
    second.timing["displacement_run_s"] = result.timing["total_s"]
    second.timing["total_s"] += result.timing["total_s"]
    outcome = ("reached the requested stretch, so that stop was an artefact of the locked elements"
               if second.history.failure is None else "stops too (its own diagnosis follows)")
    second.diagnostics.warnings.insert(0, (
        f"mesh.formulation: the displacement-only elements (the default) stopped at grip stretch "
        f"{', '.join(f'{v:.4g}' for v in critical.stretch_unstable)} with {critical.negative_eigenvalues} negative eigenvalue(s) of a local "
        f"mode while the material stayed strongly elliptic; at nu = {critical.locking_nu:g} they lock on this "
        f"non-uniform field, so the run was repeated with mesh.formulation = 'mixed' on the same mesh, which "
        f"{outcome}; these are the mixed run's results (set mesh.formulation to choose)"))
    log.warning(second.diagnostics.warnings[0])
    return second


def _run_scene(scene: Scene, on_level, specimen: Specimen | None, observe=None) -> RunResult:
    clock = time.perf_counter
    t0 = clock()
    seeded = None
    if scene.test.imperfection is not None:
        seeded = _seeded_specimen(scene, specimen or build_specimen(scene))
        if seeded.specimen is None:  # no buckling mode to seed: the first pass is the answer
            seeded.first_pass.diagnostics.warnings.append(seeded.note)
            return seeded.first_pass
        specimen = seeded.specimen
    with memory_phase("mesh"):
        prepared = prepare(scene, specimen, current())  # the run's settings, passed down to the body
    check_view(prepared)  # a camera that cannot see its face is refused before the solve
    timing = {"mesh_s": clock() - t0}
    monitor, instruments, deflection = stability_monitor(prepared), Instruments(prepared), _Deflection(prepared)
    observers: list[Observer] = [monitor, deflection, instruments] + ([on_level] if on_level else [])
    if observe is not None:  # e.g. sensitivities that back-substitute with the monitor's factor
        observers.append(observe(prepared, monitor.tangents))
    t1 = clock()
    solved = solve(prepared, monitor, observers)
    timing["solve_s"] = clock() - t1 - instruments.seconds
    t2 = clock()
    with memory_phase("measurement"):
        measured = measure(prepared, instruments)
    timing["measure_s"] = instruments.seconds + clock() - t2
    timing["total_s"] = clock() - t0
    diagnostics = _diagnostics(prepared, solved, measured, monitor, deflection.values, seeded)
    constants = _yield_screened(scene, measured, diagnostics)
    return RunResult(scene, prepared.specimen, prepared.space, measured.curve, constants,
                     solved.history, timing, diagnostics,
                     SolverObjects(prepared.body, prepared.partition, monitor.critical), measured.reference)


class _Deflection:
    """Observer: the largest lateral deflection of the centre line per level (mm)."""

    def __init__(self, prepared: Prepared):
        self.X, self.values = prepared.space.node_coordinates, []

    def __call__(self, level: Level) -> None:
        self.values.append(lateral_deflection(self.X, level.evaluation.u))


def _diagnostics(prepared: Prepared, solved: Solved, measured: Measured, monitor: StabilityMonitor,
                 deflection: list[float], seeded: "_Seeded | None") -> Diagnostics:
    scene, body = prepared.scene, prepared.body
    out = Diagnostics(
        mesh_quality=prepared.quality.as_dict(),
        linear_solver={"requested": scene.solver.linear, "newton": solved.linear_solver,
                       "choice": solved.linear_choice,
                       "direct": solver_in_use(), "amg_setups": solved.history.amg_setups,
                       "factorizations": solved.history.factorizations,
                       "stability_methods": _method_counts(monitor)},
        tangent_kernel=body.tangent_kernel,
        warnings=_warnings(scene), crosshead=measured.crosshead, uncertainty=measured.uncertainty,
        cruciform=measured.cruciform, homogeneity=measured.homogeneity, bending=measured.bending,
        stability=[r.as_dict() for r in monitor.records], lateral_deflection=deflection,
        critical=None if monitor.critical is None else monitor.critical.as_dict())
    if seeded is not None:
        out.imperfection = {"perfect_critical": seeded.first_pass.diagnostics.critical}
    if scene.effects or scene.test.protocol.name != "monotonic":
        from vlab.effects.report import effects_summary
        out.effects = effects_summary(scene, body, solved.history.levels)
    return out


def _method_counts(monitor: StabilityMonitor) -> dict[str, int]:
    """How many vetted states (accepted levels and rejected trials) each stability method decided."""
    counts: dict[str, int] = {}
    for record in monitor.records:
        counts[record.stability_method] = counts.get(record.stability_method, 0) + 1
    return counts


def _yield_screened(scene: Scene, measured: Measured, diagnostics: Diagnostics):
    """E and ν (and the crosshead modulus) withdrawn, with the reason, when plasticity set in
    before the modulus window ends (vlab.measure.yielding)."""
    if diagnostics.effects is None:
        return measured.constants
    from vlab.measure.yielding import screen_yield
    from vlab.pipeline.measure import fitted_part

    extra = {"effects": diagnostics.effects, "crosshead": diagnostics.crosshead}
    constants = screen_yield(scene, fitted_part(measured.curve, scene), measured.constants, extra)
    diagnostics.crosshead = extra["crosshead"]
    return constants


@dataclass
class _Seeded:
    """The first (perfect) pass of an imperfect test and the specimen it seeds (None: no mode)."""

    first_pass: RunResult
    specimen: Specimen | None
    note: str = ""


def _seeded_specimen(scene: Scene, specimen: Specimen) -> _Seeded:
    """Run the perfect specimen to its first loss of stability; seed its mode as imperfection."""
    perfect = dataclasses.replace(scene, test=dataclasses.replace(scene.test, imperfection=None))
    first = run_scene(perfect, specimen=specimen)
    critical = first.solver.critical_state
    if critical is None or not critical.is_buckling:
        return _Seeded(first, None, "test.imperfection: the perfect specimen did not buckle up to the "
                                    "requested stretch, so there is no mode to seed; this is the perfect run")
    moved = imperfect_specimen(specimen, first.space, critical.mode,
                               scene.test.imperfection * specimen_thickness(scene))
    return _Seeded(first, moved)


def specimen_thickness(scene: Scene) -> float:
    """The smallest cross-section dimension (mm), the scale of a buckling imperfection."""
    return SHAPES[scene.specimen.shape].thickness(scene.specimen)


def _warnings(scene: Scene) -> list[str]:
    """Caveats about the set-up (also logged)."""
    found = []
    nu = scene.material.moduli.nu
    if scene.effects or scene.test.protocol.name != "monotonic":
        from vlab.effects.build import effect_warnings
        found += effect_warnings(scene)
    if locking_prone(scene):
        cure = (f'use mesh.formulation = "mixed" (locking-free up to nu = {MIXED_NU_LIMIT:g})'
                if MODELS[scene.material.model].split is not None else
                f'mesh.formulation = "mixed" would cure it but needs material.model in '
                f'{", ".join(n for n, m in MODELS.items() if m.split is not None)}')
        found.append(f"material.nu = {nu:g} > {LOCKING_NU:g} with the displacement-only formulation: "
                     "expect volumetric locking (too stiff) wherever the field is not uniform, e.g. "
                     f"with clamped grips; homogeneous roller tests are unaffected; {cure}")
    for text in found:
        log.warning(text)
    return found
