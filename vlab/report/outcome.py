"""One model's finished test packaged for the reports: the results.json dict, the snapshot for
renders and VTU files, and model-specific evidence (a Taylor test of the spring network)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

from vlab.post.snapshot import Snapshot
from vlab.materials.registry import MODELS

__all__ = ["ModelOutcome", "outcome_of"]


@dataclass(frozen=True)
class ModelOutcome:
    """One model's test: the results.json dict, the snapshot for renders/VTU, checks of the model.

    ``source`` is the snapshot, or the RunResult it is taken from on first use of ``snapshot``
    (a report's figures, drawn from ``data`` alone, start before the snapshot is taken)."""

    model: str
    data: dict
    source: object
    checks: dict
    critical_mode: object = None  # eigenvector of the first loss of stability (full DOF vector), if any
    dic: object = None  # vlab.pipeline.dic.DicRun of a scene with [instruments.dic]

    @cached_property
    def snapshot(self) -> Snapshot:
        return self.source if isinstance(self.source, Snapshot) else _snapshot_of(self.source, self.model)


def _snapshot_of(result, label: str) -> Snapshot:
    from vlab.post.snapshot import take_snapshot

    return replace(take_snapshot(result), model=label)


def outcome_of(result, label: str | None = None, snapshot_now: bool = True) -> ModelOutcome:
    """Package a RunResult for the reports; ``label`` (default: the model name; vlab compare: a
    [compare.<label>] card) names the outcome, its folder and its curves (input.label).
    ``snapshot_now=False`` takes the snapshot when it is first used (the outcome then holds the
    result: not for outcomes sent between processes)."""
    from vlab.report.results import result_to_dict

    label = label or result.scene.material.model
    data = result_to_dict(result)
    if label != result.scene.material.model:
        data["input"]["label"] = label
    critical = result.solver.critical_state
    return ModelOutcome(label, data, _snapshot_of(result, label) if snapshot_now else result,
                        _model_checks(result), None if critical is None else critical.mode, result.dic)


def _model_checks(result) -> dict:
    """Model-specific evidence shown in the report: a Taylor test for the spring network, whose
    force and stiffness have no analytic homogeneous oracle to be checked against."""
    if MODELS[result.scene.material.model].continuum:
        return {}
    from vlab.fe.taylor import random_state, taylor_test

    body = result.solver.body
    u, v = random_state(body, 0.02 * min(body.L))
    check = taylor_test(body, u, v, h0=0.05 * min(body.L)).as_dict()
    return {"taylor": check, "springs": body.n_springs, "stiffness_factor": 6.0}
