"""The [effects] section, [material] density and the [test] protocols: parsing and refusals."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from tests.effects_helpers import BLOCK, scene
from vlab.effects import EFFECTS
from vlab.loading.protocol import ProtocolSpec, protocol_levels
from vlab.loading.schedule import monotonic_schedule
from vlab.scene import SceneError, parse_scene

VE = {"viscoelastic": {"tau": [1.0], "beta": [0.5]}}


def error(test=None, effects=None, material=None) -> str:
    with pytest.raises(SceneError) as exc:
        scene(test, effects, material)
    return str(exc.value)


def test_no_effects_section_is_the_elastic_monotonic_scene():
    s = scene()
    assert s.effects == () and s.test.protocol == ProtocolSpec() and s.material.density is None


def test_registry_lists_the_built_in_effects_with_their_keys():
    assert {"viscoelastic", "gravity"} <= set(EFFECTS)
    assert EFFECTS["viscoelastic"].keys == ("tau", "beta") and EFFECTS["viscoelastic"].role == "material"
    assert EFFECTS["gravity"].role == "load"


def test_viscoelastic_parses_with_time():
    s = scene({"ramp_time": 2.0}, VE)
    spec = s.effect("viscoelastic")
    assert spec.tau == (1.0,) and spec.beta == (0.5,) and s.test.protocol.ramp_time == 2.0


@pytest.mark.parametrize("effects, test, fragments", [
    ({"viscoelastic": {"tau": [1.0], "beta": [-0.1]}}, {"ramp_time": 1}, ["effects.viscoelastic.beta[0]", ">= 0", "-0.1"]),
    ({"viscoelastic": {"tau": [0.0], "beta": [1.0]}}, {"ramp_time": 1}, ["effects.viscoelastic.tau[0]", "> 0", "got 0"]),
    ({"viscoelastic": {"tau": [1.0, 2.0], "beta": [1.0]}}, {"ramp_time": 1}, ["effects.viscoelastic.beta", "2 numbers"]),
    ({"viscoelastic": {"tau": [1.0], "beta": [1.0], "eta": 3}}, {"ramp_time": 1}, ["unknown key 'eta'", "[effects.viscoelastic]"]),
    ({"viscoelastic": {"tau": [1.0], "beta": [1.0]}}, {}, ["effects.viscoelastic", "test.strain_rate", "test.ramp_time"]),
    ({"viscoelasticity": {}}, {}, ["unknown effect effects.viscoelasticity", "did you mean 'viscoelastic'"]),
    ({"viscoelastic": 3}, {"ramp_time": 1}, ["[effects.viscoelastic] must be a table"]),
    ({"gravity": {}}, {}, ["effects.gravity needs material.density"]),
])
def test_bad_effects_name_the_field(effects, test, fragments):
    msg = error(test, effects)
    for fragment in fragments:
        assert fragment in msg, msg


def test_gravity_direction_and_density_units():
    s = scene(effects={"gravity": {"direction": "-z", "g": 9.81}}, material={"density": 1000.0})
    assert s.material.density == pytest.approx(1e-9)  # t/mm³
    g = s.effect("gravity")
    assert g.direction == (0.0, 0.0, -1.0) and g.g == pytest.approx(9810.0)
    assert "effects.gravity.direction" in error(effects={"gravity": {"direction": "down"}},
                                                material={"density": 1000.0})
    assert "material.density" in error(material={"density": -1.0})


def test_viscoelastic_needs_the_neo_hookean_ground_law():
    assert "material.model" in error({"ramp_time": 1}, VE, {"model": "stvk"})


@pytest.mark.parametrize("test, fragments", [
    ({"protocol": "cyclic", "amplitudes": [1.2, 1.1]}, ["test.amplitudes", "rising"]),
    ({"protocol": "cyclic", "amplitudes": [1.1, 1.2], "stretch": 1.2}, ["test.stretch is not used"]),
    ({"protocol": "cyclic", "amplitudes": [1.1, 1.2], "min_stretch": 1.15}, ["test.min_stretch"]),
    ({"protocol": "relaxation"}, ["test.protocol = 'relaxation'", "test.ramp_time"]),
    ({"protocol": "relaxation", "ramp_time": 1}, ["missing required key test.hold_time"]),
    ({"protocol": "monotonic", "hold_time": 3}, ["test.hold_time applies to"]),
    ({"protocol": "load-unload", "ramp_time": 1, "strain_rate": 1}, ["not both"]),
    ({"protocol": "swing"}, ["test.protocol must be one of"]),
    ({"ramp_time": -1}, ["test.ramp_time", "> 0"]),
])
def test_bad_protocols_name_the_field(test, fragments):
    data = copy.deepcopy(BLOCK)
    data["test"].update(test)
    if test.get("protocol") == "cyclic" and "stretch" not in test:
        del data["test"]["stretch"]
    with pytest.raises(SceneError) as exc:
        parse_scene(data)
    for fragment in fragments:
        assert fragment in str(exc.value), str(exc.value)


def test_monotonic_levels_are_the_old_schedule_and_untimed():
    levels = protocol_levels(ProtocolSpec(), (1.5,), 10, (0.0005, 0.0025), 9)
    assert np.array_equal(levels.t, monotonic_schedule((1.5,), 10, (0.0005, 0.0025), 9))
    assert levels.time is None and not levels.force_held.any()


def test_cyclic_levels_rise_and_return_with_time_at_the_rate():
    p = ProtocolSpec("cyclic", amplitudes=(1.1, 1.2), min_stretch=1.05, strain_rate=0.1)
    levels = protocol_levels(p, (1.2,), 10, (0.0005, 0.0025), 0)
    stretch = 1 + 0.2 * levels.t
    peaks = [i for i in range(1, len(stretch) - 1) if stretch[i] > stretch[i - 1] and stretch[i] > stretch[i + 1]]
    assert np.allclose(stretch[peaks], [1.1, 1.2]) and stretch[-1] == pytest.approx(1.05)
    assert np.max(stretch) == pytest.approx(1.2)
    speeds = np.abs(np.diff(np.concatenate([[1.0], stretch]))) / np.diff(np.concatenate([[0.0], levels.time]))
    assert np.allclose(speeds, 0.1)


def test_creep_holds_the_force_after_the_ramp_and_hold_times_grow():
    p = ProtocolSpec("creep", ramp_time=1.0, hold_time=100.0, hold_steps=8)
    levels = protocol_levels(p, (1.2,), 5, (0.0005, 0.0025), 0)
    assert levels.force_held.tolist() == [False] * 5 + [True] * 8
    hold = np.diff(levels.time[4:])
    assert levels.time[-1] == pytest.approx(101.0) and np.all(np.diff(hold) > 0)


def test_warnings_for_effects_the_protocol_cannot_show():
    from vlab.effects.build import effect_warnings
    assert any("every beta is 0" in w for w in effect_warnings(
        scene({"ramp_time": 1}, {"viscoelastic": {"tau": [1.0], "beta": [0.0]}})))
    assert any("neither relaxes nor creeps" in w for w in effect_warnings(
        scene({"protocol": "relaxation", "ramp_time": 1, "hold_time": 5})))
