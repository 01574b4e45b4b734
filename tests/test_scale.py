"""Scale (issue #16, item 6): moduli that under- or overflow double precision are refused up front,
the residual is measured relative to the problem's own force scale (never read as 0 for want of
exponent range), and a tolerance below the round-off floor is diagnosed as such."""

import subprocess
import sys

import numpy as np
import pytest

from helpers_scenes import block_scene
from vlab.fe.newton import _norm
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene


def raw_block(E=10.0, nu=0.3, **solver):
    data = {"name": "scale", "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
            "mesh": {"size": 5.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": E, "nu": nu},
            "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.5, "steps": 4}}
    if solver:
        data["solver"] = solver
    return data


@pytest.mark.parametrize("E", [1e-300, 1e300, 1e-101, 1e101])
def test_a_modulus_outside_double_precision_is_refused_naming_the_field_and_range(E):
    with pytest.raises(SceneError, match=r"material\.E = .* outside the allowed range 1e-100\.\.1e\+100 MPa"):
        parse_scene(raw_block(E=E))


def test_a_derived_modulus_out_of_range_names_the_pair_it_came_from():
    with pytest.raises(SceneError, match=r"material\.E = 1\.04e\+100 MPa \(derived from material\.nu = 0\.3 and material\.mu = 4e\+99\)"):
        parse_scene({**raw_block(), "material": {"model": "neo-hookean", "mu": 4e99, "nu": 0.3}})


@pytest.mark.parametrize("E", [3e-100, 1e100])  # mu = E / 2.6 in range too
def test_both_ends_of_the_modulus_range_reproduce_the_analytic_curve(E):
    data = result_to_dict(run_scene(parse_scene(raw_block(E=E))))
    assert data["converged"]
    assert data["reference"]["max_relative_error_x"] < 1e-9
    assert data["measured"]["E"] == pytest.approx(E, rel=0.01)
    assert sum(data["solver"]["newton_iterations"]) > 0  # Neo-Hookean needs Newton at every scale


def test_the_residual_norm_is_not_lost_to_underflow_or_overflow():
    for scale in (1e-200, 1e-160, 1.0, 1e160, 1e200):
        a = scale * np.array([3.0, 4.0])
        assert _norm(a) == pytest.approx(5.0 * scale, rel=1e-15)
    assert _norm(np.zeros(3)) == 0.0


def test_an_out_of_range_modulus_on_the_command_line_exits_2_and_writes_nothing(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text('name = "s"\n[specimen]\nshape = "block"\nsize = [10.0, 10.0, 10.0]\n'
                     '[mesh]\nsize = 5.0\n[material]\nmodel = "neo-hookean"\nE = 1e300\nnu = 0.3\n'
                     '[test]\nkind = "uniaxial"\nstretch = 1.5\n')
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "vlab", "run", str(scene), "--out", str(out), "--no-render",
                          "--no-estimate"], capture_output=True, text=True)
    assert run.returncode == 2 and "material.E" in run.stdout + run.stderr
    assert "Traceback" not in run.stdout + run.stderr and not out.exists()


def test_a_tolerance_below_the_round_off_floor_is_diagnosed_with_the_floor():
    data = result_to_dict(run_scene(block_scene("neo-hookean", 1.5, size=5.0, steps=4, rtol=1e-14)))
    reason = data["failure"]["reason"]
    assert "round-off floor of this problem (floor ≈" in reason and "solver.rtol = 1e-14 is below it" in reason
    floor = float(reason.split("floor ≈ ")[1].split()[0])
    stall = float(reason.split("stalls at ")[1].split()[0])
    assert 1e-14 < floor and stall < 100 * floor  # what was measured: where it stalled, the floor
