"""One run of a scene reduced to the figures a study compares (a plain JSON-safe dict).

``summarize(source, knobs)`` never raises for a bad grid point: an invalid scene or mesh gives
status "invalid", a solver stop gives status "failed" with its diagnosis, anything unexpected gives
status "error" with the exception text (not cached: it may be transient). It is a module-level
function of picklable arguments so that Dask workers can run it.

Figures kept: measured E and ν, the final grip stretch, load-cell force (N) and engineering stress
(MPa); the wall-time split (mesh, assembly, linear solves, other solver work, measurement, report;
the kernels are compiled before the clock, vlab.study.warm, and that time is ``compile_s``);
peak memory; DOFs, elements, Newton iterations, factorizations, cutbacks; and, for a uniaxial block
with roller grips, the analytic homogeneous values of the same quantities (``analytic``), obtained
by applying the same fit over the same window to the analytic curve at the recorded stretches.
"""

from __future__ import annotations

import logging
import tempfile
import time
import traceback
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from vlab import __version__
from vlab.scene import SceneError, parse_scene
from vlab.study.memory import peak_memory
from vlab.study.warm import warm_kernels

log = logging.getLogger(__name__)

QUANTITIES = ("E", "nu", "final_force", "final_stress")


@dataclass(frozen=True)
class RunKnobs:
    """What beyond the scene a summary depends on (part of the cache key)."""

    time_report: bool = False  # write the run's report (plots + HTML) to a scratch folder and time it
    render: bool = False  # include the 3D renders in that report

    def as_dict(self) -> dict:
        # 2: mesh.h_eff, mesh.measure; 3: kernels compiled before the clock (timing.compile_s):
        # the cached timings of format 2 booked a first compilation as mesh time
        return asdict(self) | {"summary_format": 3}


def summarize(source: dict, knobs: RunKnobs = RunKnobs(), label: dict | None = None,
              base_dir: str = ".") -> dict:
    """Run the scene given as a raw dict, its relative paths taken from ``base_dir`` (the scene
    file's folder, absolute: a Dask worker may run in another folder); return its summary."""
    base = {"label": label or {}, "vlab_version": __version__, "knobs": knobs.as_dict()}
    try:
        scene = parse_scene(source, origin="scene", base_dir=base_dir)
    except SceneError as exc:
        return base | {"status": "invalid", "diagnosis": str(exc)}
    base["scene_hash"] = scene.content_hash()
    try:
        return base | _run(scene, knobs)
    except SceneError as exc:  # mesh below mesh.min_quality, invalid mesh
        return base | {"status": "invalid", "diagnosis": str(exc)}
    except Exception as exc:  # noqa: BLE001 - a study reports every grid point, it never aborts
        log.exception("run failed unexpectedly")
        return base | {"status": "error", "diagnosis": f"{type(exc).__name__}: {exc}",
                       "traceback": traceback.format_exc(limit=8)}


def _run(scene, knobs: RunKnobs) -> dict:
    from vlab.report.results import result_to_dict
    from vlab.run import run_scene

    compile_s = warm_kernels(scene)  # before the clock: the run times the solve, not numba
    start = time.perf_counter()
    with peak_memory() as memory:
        result = run_scene(scene)
        data = result_to_dict(result)
        report_s = _time_report(result, knobs) if knobs.time_report else None
    timing = dict(result.timing)
    timing["solve_other_s"] = max(0.0, timing["solve_s"] - timing["assembly_s"] - timing["linear_solve_s"])
    timing["report_s"] = report_s
    timing["compile_s"] = compile_s  # kernels compiled or loaded for this run (0: already warm)
    timing["wall_s"] = time.perf_counter() - start
    out = {
        "status": "ok" if data["converged"] else "failed",
        "diagnosis": None if data["converged"] else _diagnosis(data["failure"]),
        "measured": measured_quantities(data),
        "timing": timing,
        "memory": memory.as_dict(),
        "mesh": {k: data["mesh"][k] for k in ("cell", "order", "size", "elements", "nodes", "dofs")}
        | effective_size(result),
        "solver": {"newton_iterations": int(sum(data["solver"]["newton_iterations"])),
                   "factorizations": data["solver"]["factorizations"],
                   "cutbacks": int(sum(data["solver"]["cutbacks"])), "rtol": data["solver"]["rtol"],
                   "levels": len(data["solver"]["newton_iterations"])},
        "model": scene.material.model,
        "steps": scene.test.steps,
        "analytic": analytic_quantities(result),
        "stress_max_relative_error": (data.get("reference") or {}).get("max_relative_error_x"),
    }
    return out


def measured_quantities(data: dict) -> dict:
    """E, ν and the force/stress/stretch at the peak grip stretch (the last reading of a monotonic
    test; cyclic and load–unload tests end unloaded) of a results.json dict (None if not measured);
    with the crosshead modulus and, where the test was misaligned, the ASTM E1012 percent bending at the
    gauge centre (four gauges, and each pair's signed two-gauge value)."""
    curve = data["curve"]
    stretch = curve.get("stretch") or []
    peak = int(np.argmax(np.abs(np.asarray(stretch, dtype=float) - 1.0))) if stretch else -1
    last = (lambda key: curve[key][peak] if curve.get(key) else None)
    out = {"E": data["measured"]["E"], "nu": data["measured"]["nu"], "E_crosshead": data["measured"].get("E_crosshead"),
           "final_force": last("force"), "final_stress": last("stress"), "final_stretch": last("stretch")}
    bending = (data.get("bending") or {}).get("small_strain")  # a misaligned test's face gauges
    keys = ("percent_bending", "percent_bending_thickness", "percent_bending_width")
    return out | ({k: bending[k] for k in keys} if bending else {})


def effective_size(result) -> dict:
    """The mesh's effective element size h_eff = (Ω / n_elements)^(1/d) (mm), Ω the reference volume
    (d = 3) or area (d = 2, a sheet: dx carries the thickness, divided out here), and Ω itself.

    The nominal mesh.size is only an upper bound on the element edge: a structured mesher rounds
    element counts up per segment (a dogbone keeps one element across its 2 mm half-thickness from
    mesh.size 1 to 12), so halving mesh.size may multiply the element count by far less than 2^d.
    Richardson extrapolation needs the size that actually changed; h_eff is it (the same for every
    element order; the DOFs grow with the order at fixed h_eff)."""
    space = result.space
    dim = int(space.basis.mesh.dim())
    thickness = (result.specimen.sheet_thickness or 1.0) if dim == 2 else 1.0
    measure = float(np.sum(space.dx)) / thickness
    return {"measure": measure, "h_eff": (measure / int(space.basis.nelems)) ** (1.0 / dim)}


def analytic_quantities(result) -> dict | None:
    """The analytic homogeneous E, ν, final force and stress of a uniaxial roller block, or None."""
    from vlab.measure.fit import FitError, fit_line

    ref, curve, scene = result.reference, result.curve, result.scene
    if not ref or curve.kind != "uniaxial" or "stress_x" not in ref or not ref["stress_x"]:
        return None
    n = len(ref["stress_x"])
    strain = np.asarray(curve.stretch[0][:n]) - 1.0  # homogeneous: extensometer strain = grip strain
    stress = np.asarray(ref["stress_x"])
    lateral = np.asarray(ref["lateral_stretch"]) - 1.0
    window, method = scene.measure.modulus_window, scene.measure.fit
    try:
        E = fit_line(strain, stress, window, method).slope
        nu = -fit_line(strain, lateral, window, method).slope
    except FitError:
        E = nu = None
    area0 = curve.area0.get(0)
    final_stress = float(stress[-1]) if n == len(curve.t) else None
    return {"E": E, "nu": nu, "final_stress": final_stress,
            "final_force": None if final_stress is None or area0 is None else final_stress * area0}


def _time_report(result, knobs: RunKnobs) -> float:
    from vlab.report.writer import ReportOptions, write_run

    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="vlab-report-") as scratch:
        write_run(result, Path(scratch) / "report", None, ReportOptions(render=knobs.render, vtu=False))
    return time.perf_counter() - start


def _diagnosis(failure: dict | None) -> str:
    if not failure:
        return "stopped"
    residuals = ", ".join(f"{r:.2e}" for r in (failure.get("residual_history") or [])[-4:])
    return (f"stopped at step {failure['step']}, stretch {failure['stretch']}: {failure['reason']}; "
            f"last converged stretch {failure['last_converged_stretch']}"
            + (f"; last residuals {residuals}" if residuals else ""))
