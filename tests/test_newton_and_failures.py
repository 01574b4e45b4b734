"""Newton converges quadratically; the linear model needs no iteration; failures are diagnosed."""

import json

import numpy as np
import pytest
from scenes import scene_dict

from vlab.report.results import result_to_dict
from vlab.report.results import observed_order
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene


def test_newton_converges_quadratically_near_the_solution():
    data = result_to_dict(run_scene(parse_scene(scene_dict(
        mesh={"cell": "tet", "size": 4.0}, test={"stretch": 1.6, "steps": 4, "grips": "clamped"},
        solver={"rtol": 1e-12, "newton": "exact"}))))
    orders = [p for p in data["solver"]["observed_order"] if p is not None]
    assert orders and min(orders) > 1.8
    for history in data["solver"]["residual_history"]:
        assert history[-1] <= 1e-12


def test_linear_model_uses_one_solve_per_step_and_no_newton_iteration():
    result = run_scene(parse_scene(scene_dict(material={"model": "linear", "E": 10, "nu": 0.3},
                                              test={"grips": "clamped", "steps": 5})))
    assert all(level.iterations == 0 for level in result.history.levels)
    assert result.history.factorizations == 1


def test_observed_order_reads_the_residual_history():
    assert observed_order([1e-2, 1e-4, 1e-8]) == pytest.approx(2.0)
    assert observed_order([1e-2, 1e-3]) is None


def test_a_request_with_no_admissible_state_is_refused_before_solving():
    # StVK in uniaxial tension has no equilibrium with free lateral faces beyond sqrt(1 + 1/nu).
    data = result_to_dict(run_scene(parse_scene(scene_dict(
        material={"model": "stvk", "E": 10, "nu": 0.45}, test={"stretch": 2.2, "steps": 4}))))
    assert data["converged"] is False
    assert "no admissible state beyond stretch 1.795" in data["failure"]["reason"]
    assert data["curve"]["stress"] == []


def test_a_failed_test_reports_step_stretch_reason_and_history_without_nan():
    # StVK in compression passes its limit point at stretch 1/sqrt(3): the test must stop there.
    result = run_scene(parse_scene(scene_dict(
        material={"model": "stvk", "E": 10, "nu": 0.3}, test={"stretch": 0.4, "steps": 4},
        mesh={"size": 10.0})))
    data = result_to_dict(result)
    assert data["converged"] is False
    failure = data["failure"]
    assert failure["step"] >= 1 and "no admissible state beyond stretch" in failure["reason"]
    assert 1 / np.sqrt(3) - 0.01 < failure["last_converged_stretch"][0] < 0.75
    assert failure["residual_history"]
    text = json.dumps(data)
    assert "NaN" not in text and "Infinity" not in text
    # The recorded curve stops at the last converged level and holds only finite numbers.
    assert np.all(np.isfinite(data["curve"]["stress"]))
    assert min(data["curve"]["stretch"]) >= failure["last_converged_stretch"][0] - 1e-12


def test_factor_reuse_reaches_the_exact_newton_answer_with_fewer_factorizations():
    runs = {mode: run_scene(parse_scene(scene_dict(
        mesh={"cell": "hex", "size": 2.0}, test={"stretch": 1.5, "steps": 10, "grips": "clamped"},
        solver={"newton": mode}))) for mode in ("reuse", "exact")}
    data = {mode: result_to_dict(r) for mode, r in runs.items()}
    assert all(d["converged"] for d in data.values())
    reuse, exact = data["reuse"]["solver"], data["exact"]["solver"]
    assert reuse["newton"] == "reuse" and exact["newton"] == "exact"
    assert all(h[-1] <= 1e-8 for h in reuse["residual_history"])
    # both converged to rtol: the final grip force agrees to the tolerance, not to round-off
    f = [r.curve.force[0][-1] for r in runs.values()]
    assert f[0] == pytest.approx(f[1], rel=1e-8)
    # measured: 20 vs 31 factorizations, and no exact Newton iteration at all with reuse
    assert reuse["factorizations"] < 0.7 * exact["factorizations"]
    assert sum(reuse["exact_iterations"]) < sum(exact["exact_iterations"])


def test_an_unknown_newton_mode_is_refused_with_the_allowed_values():
    with pytest.raises(SceneError, match=r"solver\.newton.*reuse.*exact"):
        parse_scene(scene_dict(solver={"newton": "quasi"}))
