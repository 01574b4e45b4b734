"""Stage 3 of a run: the instruments (an observer of every converged level) and, at the end,
what they measured: the curve (noisy if the scene declares instrument noise), E and ν fitted on
the first loading ramp, the crosshead modulus, the analytic homogeneous reference (roller-gripped
blocks and sheets) and the gauge-section and cruciform-centre statistics."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from vlab.fe.stepping import Level
from vlab.measure.centre_stress import CentreStressProbe, centre_report
from vlab.loading.kinds import kind_of
from vlab.measure import kinds as provided
from vlab.measure.elastic_constants import ElasticConstants, elastic_constants, first_loading
from vlab.measure.recorder import Curve, Recorder
from vlab.pipeline.prepare import Prepared

__all__ = ["Instruments", "Measured", "measure"]


class Instruments:
    """Load cell, extensometers and probes read at every converged level (an observer); the time
    spent reading is kept apart from the solve's (``seconds``)."""

    def __init__(self, prepared: Prepared):
        space, specimen, oracle = prepared.space, prepared.specimen, prepared.oracle
        self.body = prepared.body
        test = prepared.scene.test
        kind = kind_of(test)
        self.recorder = Recorder(space, specimen, kind, test.targets, prepared.loading, oracle,
                                 CentreStressProbe.build(space, specimen, oracle))
        if test.grip_slip:  # the crosshead reads the clamps' travel plus the slip C F (Curve.crosshead_strain)
            self.recorder.curve.slip = test.grip_slip / specimen.grip_separation[0]
        self.probe = provided.probe(kind, space, specimen, oracle) if oracle is not None else None
        self.homogeneity: list[dict] = []
        self.bending = None  # the face gauges of a misaligned test (vlab.measure.bending)
        if test.misalignment is not None:
            from vlab.measure.bending import FaceGauges
            self.bending = FaceGauges(space, specimen)
        self.seconds = 0.0

    def __call__(self, level: Level) -> None:
        t = time.perf_counter()
        self.recorder(level)
        if self.body.history is not None:  # a history body keeps its cells' state per level
            self.body.history.keep_cells(level.evaluation)
        if self.probe is not None:
            self.homogeneity.append(self.probe.read(level.evaluation.F, self.recorder.curve.force[0][-1]))
        if self.bending is not None:
            self.bending.read(level.evaluation.u)
        self.seconds += time.perf_counter() - t


@dataclass(frozen=True)
class Measured:
    curve: Curve
    constants: ElasticConstants
    reference: dict | None
    crosshead: dict | None
    uncertainty: dict | None
    cruciform: dict | None
    homogeneity: dict | None
    bending: dict | None = None  # ASTM E1012 percent bending from the face gauges (misaligned tests)


def measure(prepared: Prepared, instruments: Instruments) -> Measured:
    """What the instruments read, reduced to the quantities results.json reports."""
    scene = prepared.scene
    window, fit = scene.measure.modulus_window, scene.measure.fit
    curve = instruments.recorder.curve
    constants = elastic_constants(fitted_part(curve, scene), window, fit)
    uncertainty = None
    if scene.effect("noise") is not None:  # the instruments' readings replace the exact ones
        from vlab.measure.noise import measure_with_noise
        curve, constants, uncertainty = measure_with_noise(scene.effect("noise"), curve, prepared.specimen,
                                                           scene.measure)
    rows = instruments.homogeneity
    bending = None
    if instruments.bending is not None:
        from vlab.measure.bending import bending_report
        bending = bending_report(instruments.bending, instruments.recorder.curve, window)
    return Measured(curve, constants, _reference(prepared, curve),
                    crosshead=provided.crosshead(kind_of(scene.test), fitted_part(curve, scene), window, fit),
                    uncertainty=uncertainty,
                    cruciform=centre_report(curve, window, fit),
                    homogeneity=_homogeneity_report(curve, rows, window) if rows else None, bending=bending)


def fitted_part(curve: Curve, scene) -> Curve:
    """E and ν are fitted on the first loading ramp only."""
    return first_loading(curve) if scene.test.protocol.unloads else curve


def _reference(prepared: Prepared, curve: Curve) -> dict | None:
    """The test kind's analytic homogeneous curve and the largest relative error of the measured
    stress (vlab.loading.kinds), where the kind has an oracle for this shape and grips."""
    material, scene = prepared.oracle, prepared.scene
    kind = kind_of(scene.test)
    if material is None or not kind.has_oracle(prepared.specimen.shape, scene.test.grips):
        return None
    return kind.reference(material, curve)


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
