"""Words for what was found (issue #16, item 5): each diagnosis names only what was measured."""

import pytest

from helpers_scenes import block_scene
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import parse_scene


def plastic_strip(yield_stress: float, **test) -> dict:
    """A 100 x 10 x 1 mm strip between clamps in tension, perfectly plastic above yield_stress."""
    return {"name": "strip", "specimen": {"shape": "block", "size": [100.0, 10.0, 1.0]},
            "mesh": {"size": 2.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
            "test": {"kind": "uniaxial", "grips": "clamped", "stretch": 1.03, "steps": 3, **test},
            "effects": {"plasticity": {"yield_stress": yield_stress}}}


def test_an_unstable_state_is_no_stable_state_not_no_admissible_state():
    # StVK on a finer mesh loses positive definiteness before its limit point (a state exists)
    data = result_to_dict(run_scene(block_scene("stvk", 0.62, size=2.5, steps=10)))
    reason = data["failure"]["reason"]
    assert reason.startswith("no stable state beyond stretch") and "negative eigenvalue" in reason
    assert "admissible" not in reason


@pytest.fixture(scope="module")
def yielded_strip() -> dict:
    """Measured (main before the fix): "buckling … set test.imperfection" and E = 0.0024 MPa."""
    return result_to_dict(run_scene(parse_scene(plastic_strip(1e-6))))


def test_a_sideways_mode_in_tension_is_not_buckling_and_asks_for_no_imperfection(yielded_strip):
    data = yielded_strip
    reason = data["failure"]["reason"]
    assert "buckling —" not in reason and "test.imperfection" not in reason
    assert "bifurcation in tension" in reason and "not buckling" in reason
    assert "the material has yielded: accumulated plastic strain up to" in reason
    assert data["critical"]["kind"] == "bifurcation in tension (sideways mode, not buckling)"
    assert data["critical"]["lateral_fraction"] > 0.5  # measured: sections do move sideways


def test_a_material_that_yields_before_the_modulus_window_reports_no_modulus_and_why(yielded_strip):
    data = yielded_strip
    m = data["measured"]
    assert m["E"] is None and m["nu"] is None and m["E_crosshead"] is None
    assert m["E_fit"] is None and m["E_crosshead_fit"] is None  # no R² of a fit that is not E
    assert m["note"].startswith("not measurable: the material yields before the modulus window ends")
    assert "effects.plasticity.yield_stress = 1e-06 MPa" in m["note"] and "σ_y0/E = 1e-07" in m["note"]


def test_a_roller_block_that_yields_early_reports_no_negative_modulus():
    raw = plastic_strip(1e-9)
    raw["specimen"]["size"], raw["mesh"]["size"] = [10.0, 10.0, 10.0], 5.0
    raw["test"]["grips"] = "roller"
    m = result_to_dict(run_scene(parse_scene(raw)))["measured"]
    assert m["E"] is None and "yields before the modulus window" in m["note"]


def test_a_material_that_stays_elastic_in_the_window_keeps_its_modulus():
    raw = plastic_strip(1.0)
    raw["specimen"]["size"], raw["mesh"]["size"] = [10.0, 10.0, 10.0], 5.0
    raw["test"]["grips"] = "roller"
    data = result_to_dict(run_scene(parse_scene(raw)))
    assert data["measured"]["E"] == pytest.approx(10.0, rel=0.01)  # yield strain 0.1 > 0.0025


def test_a_clamped_dogbone_a_micron_thick_is_diagnosed_as_ill_conditioned_not_free():
    raw = {"name": "thin", "specimen": {"shape": "dogbone", "standard": "ISO 527-2 1BA", "thickness": 0.001},
           "mesh": {"size": 2.5, "min_quality": 1e-4}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
           "test": {"kind": "uniaxial", "grips": "clamped", "stretch": 1.2, "steps": 2}}
    reason = result_to_dict(run_scene(parse_scene(raw)))["failure"]["reason"]
    assert "grips leave the specimen free" not in reason
    assert "although the grips restrain every rigid-body mode" in reason and "ill-conditioning by scale" in reason
    lowest = float(reason.split("its lowest eigenvalue is ")[1].split()[0])
    assert 0 < lowest < 1e-10  # measured: positive, but below the zero tolerance
    assert "along z" in reason and "0.001 mm" in reason and 'specimen.shape = "sheet"' in reason
