"""Grip slip (issue 35): the specimen slips in the grips by C·F (test.grip_slip = C, mm/N), so the
crosshead reads the clamps' travel plus the slip and the crosshead modulus falls, while the
extensometer on the specimen does not see it.

Known answer on a linear block in roller grips (homogeneous: F = k Δ with k = E_c A0/L_grip over
the crosshead's own E_c): the crosshead reads Δ + C F = Δ (1 + C k), so

    E_c(C) = E_c / (1 + C k) = E_c (1 − s),   s = C k/(1 + C k) = C F/(Δ + C F)

(s the slip's fraction of the crosshead travel, what a lab sees comparing crosshead and
extensometer), and E from the extensometer is unchanged to round-off.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from vlab.fields import SceneError
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import parse_scene
from vlab.study.summary import RunKnobs, summarize
from vlab.uncertainty.budget import compute_budget
from vlab.uncertainty.spec import parse_uncertainty

SIZE = (20.0, 5.0, 2.0)  # L = grip separation, W, T (mm)
E_CARD = 1000.0


def _source(slip=None, uncertainty=None, kind="uniaxial"):
    test = {"kind": kind, "grips": "roller", "stretch": 1.004, "steps": 4}
    if slip is not None:
        test["grip_slip"] = slip
    src = {"name": "slip", "specimen": {"shape": "block", "size": list(SIZE)}, "mesh": {"size": 5.0, "cell": "hex"},
           "material": {"model": "linear", "E": E_CARD, "nu": 0.3}, "test": test}
    return src | ({"uncertainty": uncertainty} if uncertainty is not None else {})


def _compliance(E_c: float, s: float) -> float:
    """C (mm/N) that makes the slip the fraction s of the crosshead travel: C k = s/(1 − s)."""
    L, W, T = SIZE
    return s / (1 - s) / (E_c * W * T / L)


def test_slip_fraction_s_lowers_the_crosshead_modulus_to_E_c_times_1_minus_s_and_leaves_E_alone():
    free = result_to_dict(run_scene(parse_scene(_source())))
    E_c, E = free["measured"]["E_crosshead"], free["measured"]["E"]
    for s in (0.02, 0.1, 0.3):
        r = result_to_dict(run_scene(parse_scene(_source(_compliance(E_c, s)))))
        assert r["measured"]["E_crosshead"] == pytest.approx(E_c * (1 - s), rel=1e-9)
        assert r["measured"]["E"] == pytest.approx(E, rel=1e-12)
        # the curve's crosshead strain is the clamps' travel plus the slip, C F / L_grip
        F, lam = np.array(r["curve"]["force"]), np.array(r["curve"]["stretch"])
        expect = lam - 1 + _compliance(E_c, s) * F / SIZE[0]
        assert np.allclose(r["curve"]["crosshead_strain"], expect, rtol=1e-12)
        share = _compliance(E_c, s) * F[-1] / (SIZE[0] * r["curve"]["crosshead_strain"][-1])
        assert share == pytest.approx(s, rel=1e-9)


def _in_process(points, what):
    out = [summarize(p.source, RunKnobs(), p.label, p.base_dir) | {"cache_hit": False} for p in points]
    return SimpleNamespace(summaries=out, cache_hits=0, computed=len(out), seconds={})


def test_the_budget_draws_slip_on_0_to_c_max_the_crosshead_e_carries_it_the_extensometer_e_does_not():
    E_c = result_to_dict(run_scene(parse_scene(_source())))["measured"]["E_crosshead"]
    c_max = _compliance(E_c, 0.1)
    src = _source(uncertainty={"samples": 12, "grip_slip": c_max, "load_cell_class": 1, "extensometer_class": 1,
                               "resolution": False})
    scene = parse_scene(src)
    spec = parse_uncertainty(src["uncertainty"], scene)
    (slip,) = [s for s in spec.sources if s.kind == "slip"]
    assert slip.centre == slip.half_width == c_max / 2 and slip.u == pytest.approx(c_max / (2 * math.sqrt(3)))
    budget, runs = compute_budget(src, spec, ".", _in_process, scene.measure.modulus_window[0])
    rows = {q: {r["input"]: r for r in budget[q]["contributions"]} for q in ("E", "E_crosshead")}
    assert abs(rows["E"]["grip slip"]["sensitivity"]) < 1e-9 * E_c / c_max  # round-off
    assert rows["E"]["grip slip"]["share"] < 1e-12
    # E_c(C) = 1/(1/E_c + C a), a = A0/L: dE_c/dC = −a E_c(C)², at the centre C = c_max/2 (central
    # difference: O(u²) off)
    a = SIZE[1] * SIZE[2] / SIZE[0]
    at_centre = 1 / (1 / E_c + a * c_max / 2)
    assert budget["E_crosshead"]["nominal"] == pytest.approx(at_centre, rel=1e-9)
    assert rows["E_crosshead"]["grip slip"]["sensitivity"] == pytest.approx(-a * at_centre**2, rel=1e-3)
    assert rows["E_crosshead"]["grip slip"]["share"] > 0.5  # slip of up to 10 % outweighs the load cell
    for d, s, Ec in zip(runs.deltas, runs.summaries, runs.E_crosshead):
        C = c_max / 2 + d["grip slip"]
        assert 0 <= C <= c_max
        assert s["measured"]["E_crosshead"] == pytest.approx(1 / (1 / E_c + a * C), rel=1e-9)
        assert Ec == pytest.approx(s["measured"]["E_crosshead"] * (1 + d["load cell"]), rel=1e-12)


@pytest.mark.parametrize("src, needle", [
    (_source(-1e-4), "test.grip_slip must be >= 0 and <= 10"),
    (_source("0.1"), "test.grip_slip must be a number"),
    (_source(1e-4, kind="planar"), "test.grip_slip applies to test.kind = 'uniaxial'"),
    (_source(uncertainty={"grip_slip": -1}), "uncertainty.grip_slip must be >= 0 and <= 10"),
    (_source(1e-4, uncertainty={"grip_slip": 1e-4}), "uncertainty.grip_slip draws the slip compliance"),
])
def test_bad_slip_is_refused_naming_the_field(src, needle):
    with pytest.raises(SceneError, match=needle.replace(".", r"\.").replace("(", r"\(")):
        parse_scene(src)


@pytest.mark.parametrize("command, extra, field", [
    ("run", "grip_slip = -0.001\n", "test.grip_slip"),
    ("budget", "[uncertainty]\ngrip_slip = -0.001\n", "uncertainty.grip_slip"),
])
def test_the_cli_exits_2_naming_the_slip_field_and_writes_nothing(tmp_path, command, extra, field):
    from typer.testing import CliRunner

    from helpers_scenes import block_toml
    from vlab.cli import app

    scene = tmp_path / "slip.toml"
    scene.write_text(block_toml("slip") + extra)
    res = CliRunner().invoke(app, [command, str(scene), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2 and f"{field} must be >= 0" in " ".join(res.output.split()), res.output
    assert "Traceback" not in res.output and not (tmp_path / "out").exists()
