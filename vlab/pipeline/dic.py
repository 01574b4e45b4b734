"""Stage 4 of a run whose scene has ``[instruments.dic]``: the camera, the DIC and what they measure.

Before the solve, ``check_view`` builds the camera on the specimen's face and refuses (SceneError,
exit 2, nothing written) a setting out of range, a missing face or a camera that cannot see it.
After the solve, ``with_dic`` renders the reference and every converged level from the vertices'
displacement, correlates them (vlab.dic.instrument.record), and measures:

- the DIC virtual extensometer (vlab.dic.extensometer): E and ν fitted exactly like the point
  extensometers' (same first-loading rows, modulus window and fit), from the gauge area's mean
  DIC strains instead of the gauge marks;
- FE against DIC levelled (vlab.dic.levelled) at every level;
- the levels table: grip displacement Δ = (λ_grip − 1) L₀ (mm, L₀ the full specimen's grip
  separation) and load-cell force F (N) of each level.

A scene without the table imports none of vlab.dic and costs nothing.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np

from vlab.fields import SceneError

__all__ = ["DicRun", "check_view", "with_dic"]


@dataclass
class DicRun:
    """A run's DIC: the camera's record (images, fields, noise floor), the gauge-area strains and
    the virtual extensometer's constants, FE-vs-DIC levelled (per level the differences, at the
    last level the levelled fields) and the levels table."""

    record: object  # vlab.dic.instrument.Record
    gauge: dict  # vlab.dic.extensometer.gauge_strains
    constants: object | None  # ElasticConstants of the virtual extensometer, None if not measured
    differences: list[dict]  # per level: vlab.dic.levelled.difference
    levelled_last: dict | None  # the last level's levelled FE fields (grid arrays)
    gauge_last: np.ndarray | None  # the last level's gauge area (grid bool)
    displacement: list[float | None]  # mm per level
    force: list[float]  # N per level
    timing: dict


def _spec(scene):
    return None if scene.instruments is None else scene.instruments.dic


def check_view(prepared) -> None:
    """SceneError naming the setting if the scene's camera cannot be built or cannot see its face."""
    spec = _spec(prepared.scene)
    if spec is not None:
        _view(spec, prepared.specimen.mesh)


def _view(spec, mesh):
    from vlab.dic.correlate import DICError
    from vlab.dic.instrument import CameraError, FaceError, build_view

    try:
        return build_view(spec, mesh)
    except (CameraError, DICError) as exc:
        raise SceneError(f"instruments.dic.{exc}") from None
    except FaceError as exc:
        raise SceneError(f"instruments.dic.face = {spec.face!r}: {exc}") from None


def with_dic(result):
    """``result`` with ``dic`` set (a DicRun) when its scene has [instruments.dic]."""
    spec = _spec(result.scene)
    if spec is None:
        return result
    from vlab.dic.extensometer import gauge_area, gauge_strains
    from vlab.dic.instrument import record
    from vlab.dic.levelled import FeProbe, difference

    start = time.perf_counter()
    view = _view(spec, result.specimen.mesh)
    levels, dim, n = result.history.levels, result.space.dim, result.specimen.mesh.nvertices
    frames = [np.zeros((n, 3))] + [_in_3d(lv.evaluation.u.reshape(-1, dim)[:n]) for lv in levels]
    rec = record(view, frames, spec.metrics)
    t0 = time.perf_counter()
    gauge = gauge_strains(view, result.specimen, rec.fields)
    differences, last, area = [], None, None
    if rec.fields:
        probe = FeProbe(view, rec.fields[0])
        for u, field in zip(frames[1:], rec.fields):
            last = probe.levelled(u, field)
            differences.append(difference(field, last))
        area = gauge_area(view, result.specimen, rec.fields[-1]) if "axial" in gauge else None
    displacement, force = _levels_table(result)
    timing = rec.timing | {"compare_s": time.perf_counter() - t0}
    run = DicRun(rec, gauge, _constants(result, gauge), differences, last, area, displacement, force, timing)
    timing["total_s"] = time.perf_counter() - start
    result.timing["dic_s"] = timing["total_s"]
    result.timing["total_s"] = result.timing.get("total_s", 0.0) + timing["total_s"]
    return dataclasses.replace(result, dic=run)


def _in_3d(u: np.ndarray) -> np.ndarray:
    return u if u.shape[1] == 3 else np.hstack([u, np.zeros((len(u), 3 - u.shape[1]))])


def _constants(result, gauge: dict):
    """E and ν of the virtual extensometer: the run's curve with the gauge-area strains in place
    of the extensometers', fitted like the point extensometer's (vlab.pipeline.measure)."""
    from vlab.measure.elastic_constants import elastic_constants
    from vlab.pipeline.measure import fitted_part

    curve = result.curve
    if "axial" not in gauge or curve.kind != "uniaxial" or len(gauge["axial"]) != len(curve.t):
        return None
    dic_curve = dataclasses.replace(curve, strain={**curve.strain, 0: list(gauge["axial"])},
                                    transverse_strain=list(gauge["transverse"]))
    measure = result.scene.measure
    return elastic_constants(fitted_part(dic_curve, result.scene), measure.modulus_window, measure.fit)


def _levels_table(result) -> tuple[list[float | None], list[float]]:
    """Per level the grip displacement (λ − 1) L₀ (mm; None without a grip separation on x) and
    the load-cell force (N)."""
    curve = result.curve
    sep = (getattr(result.specimen, "grip_separation", None) or {}).get(0)
    stretch = curve.stretch.get(0, [])
    displacement = [None if sep is None else (s - 1.0) * float(sep) for s in stretch]
    return displacement, [float(f) for f in curve.force.get(0, [])]
