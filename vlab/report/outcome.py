"""One model's finished test packaged for the reports: the results.json dict, the snapshot for
renders and VTU files, and model-specific evidence (a Taylor test of the spring network)."""

from __future__ import annotations

from dataclasses import dataclass

from vlab.post.snapshot import Snapshot
from vlab.scene import SPRING_NETWORK

__all__ = ["ModelOutcome", "outcome_of"]


@dataclass(frozen=True)
class ModelOutcome:
    """One model's test: the results.json dict, the snapshot for renders/VTU, checks of the model."""

    model: str
    data: dict
    snapshot: Snapshot
    checks: dict
    critical_mode: object = None  # eigenvector of the first loss of stability (full DOF vector), if any


def outcome_of(result) -> ModelOutcome:
    """Package a RunResult for the reports."""
    from vlab.post.snapshot import take_snapshot
    from vlab.report.results import result_to_dict

    critical = result.extra.get("critical_state")
    return ModelOutcome(result.scene.material.model, result_to_dict(result), take_snapshot(result),
                        _model_checks(result), None if critical is None else critical.mode)


def _model_checks(result) -> dict:
    """Model-specific evidence shown in the report: a Taylor test for the spring network, whose
    force and stiffness have no analytic homogeneous oracle to be checked against."""
    if result.scene.material.model != SPRING_NETWORK:
        return {}
    from vlab.fe.taylor import random_state, taylor_test

    body = result.extra["body"]
    u, v = random_state(body, 0.02 * min(body.L))
    check = taylor_test(body, u, v, h0=0.05 * min(body.L)).as_dict()
    return {"taylor": check, "springs": body.n_springs, "stiffness_factor": 6.0}
