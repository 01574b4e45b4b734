"""Load limit points are decided from the tangent along the prescribed path, not per-axis forces
(issue #16, item 4): a biaxial test with one axis in compression is not a limit point."""

import pytest

from helpers_scenes import block_scene
from vlab.report.results import result_to_dict
from vlab.run import run_scene


@pytest.mark.parametrize("model,sy", [("neo-hookean", 0.9), ("neo-hookean", 0.95), ("neo-hookean", 0.99),
                                      ("stvk-volumetric", 0.9), ("linear", 0.85), ("linear", 0.9)])
def test_a_biaxial_block_with_one_axis_in_compression_runs_to_its_analytic_curve(model, sy):
    data = result_to_dict(run_scene(block_scene(model, [1.5, sy], steps=4)))
    assert data["converged"], data["failure"]
    assert data["curve"]["stretch"][-1] == pytest.approx(1.5)
    assert all(s["accepted"] and not s["limit_point"] for s in data["stability"])
    assert all(s["path_stiffness"] > 0 for s in data["stability"])
    assert data["reference"]["max_relative_error_x"] < 1e-8
    assert data["reference"]["max_relative_error_y"] < 1e-8


def test_the_y_force_passes_through_zero_without_being_called_a_limit_point():
    # nu = 0.3, sy = 0.87: the lateral push of x starts the y force in tension (its magnitude
    # rises, peaks at 2.1 N and falls), then it turns compressive (−7.2 N at the end)
    data = result_to_dict(run_scene(block_scene("neo-hookean", [1.5, 0.87], steps=8)))
    fy = data["curve"]["force_y"]
    assert data["converged"] and max(fy) > 0 > min(fy)


def test_an_axis_with_no_stress_change_gets_no_weight_in_the_biaxial_modulus():
    # linear, nu = 0.3, sy − 1 = −0.3 (sx − 1): sigma_y ≡ 0, its fit slope is 0 (E was halved to 5)
    data = result_to_dict(run_scene(block_scene("linear", [1.5, 0.85], steps=2)))
    assert data["measured"]["E"] == pytest.approx(10.0, rel=1e-9)
    assert data["measured"]["nu"] == pytest.approx(0.3, rel=1e-9)


def test_stvk_in_compression_still_stops_at_its_load_maximum_with_the_path_stiffness_named():
    data = result_to_dict(run_scene(block_scene("stvk", 0.3, size=10.0, steps=20)))
    reason = data["failure"]["reason"]
    assert reason.startswith("load limit point beyond stretch") and "Q = ûᵀf" in reason
    assert "no admissible state" not in reason  # the state beyond exists; it is a load maximum
    rejected = data["stability"][-1]
    assert rejected["limit_point"] and (rejected["path_stiffness"] is None or rejected["path_stiffness"] <= 0
                                        or rejected["path_load"] < data["stability"][-2]["path_load"])
