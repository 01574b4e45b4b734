"""The test-kind registry: planar (pure shear) and simple shear against their analytic states,
their symmetry in γ, the incompressible limits, their scene grammar, and that no code outside the
kinds dispatches on how long a stretch list is."""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from vlab.loading.kinds import KINDS
from vlab.materials import make_material
from vlab.materials.homogeneous import planar, simple_shear
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import MODELS, SPRING_NETWORK, SceneError, parse_scene

try:  # the rubber models' test cards (C10, mu/alpha, ...), once the model library is there
    from rubber_cards import CARDS as RUBBER_CARDS
except ImportError:
    RUBBER_CARDS = {}

PACKAGE = Path(__file__).resolve().parents[1] / "vlab"
CONTINUUM = [m for m in MODELS if m != SPRING_NETWORK]  # every continuum model of the registry


def card(model: str) -> dict:
    """The model's test card: a rubber card with K = 20 MPa, else E = 10 MPa, ν = 0.3."""
    return ({k: v for k, v in RUBBER_CARDS[model].items() if k != "model"} | {"K": 20.0}
            if model in RUBBER_CARDS else {"E": 10.0, "nu": 0.3})


def block_scene(model: str, test: dict, material: dict | None = None, cell: str = "hex") -> dict:
    return {"name": "kind", "specimen": {"shape": "block", "size": [4.0, 3.0, 2.0]},
            "mesh": {"size": 1.0, "cell": cell},
            "material": {"model": model} | (material or card(model)),
            "test": {"steps": 4} | test}


@cache
def run(model: str, kind: str, load: float, cell: str = "hex", K_over_mu: float | None = None) -> dict:
    key = "shear" if kind == "simple-shear" else "stretch"
    grips = "kinematic" if kind == "simple-shear" else "roller"
    material = None if K_over_mu is None else {"mu": 1.0, "K": K_over_mu}
    scene = parse_scene(block_scene(model, {"kind": kind, "grips": grips, key: load}, material, cell))
    return result_to_dict(run_scene(scene))


CASES = [("planar", 1.3), ("planar", 0.9), ("simple-shear", 0.4), ("simple-shear", -0.4)]


@pytest.mark.parametrize("kind,load", CASES, ids=[f"{k}-{v}" for k, v in CASES])
@pytest.mark.parametrize("model", CONTINUUM)
def test_every_model_on_the_oracle_block_of_a_new_kind_follows_its_analytic_curve_at_every_step(model, kind, load):
    data = run(model, kind, load)
    assert data["converged"], data["failure"]
    ref = data["reference"]
    errors = [v for k, v in ref.items() if k.startswith("max_")]
    assert errors and max(errors) < 1e-6, ref
    n = len(data["curve"]["stretch" if kind == "planar" else "shear"])
    assert len(ref["stress_x" if kind == "planar" else "shear_stress"]) == n  # every recorded step


def test_the_kinematic_shear_load_cells_are_exact_on_tetrahedra_too():
    ref = run("neo-hookean", "simple-shear", 0.4, "tet")["reference"]
    assert ref["max_relative_error_shear"] < 1e-9 and ref["max_error_normal_over_shear"] < 1e-9


@pytest.mark.parametrize("model", CONTINUUM)
def test_simple_shear_stress_is_odd_and_normal_stresses_even_in_gamma(model):
    up, down = run(model, "simple-shear", 0.4)["curve"], run(model, "simple-shear", -0.4)["curve"]
    np.testing.assert_allclose(down["shear"], -np.array(up["shear"]), rtol=0, atol=1e-15)
    scale = np.max(np.abs(up["shear_stress"]))
    np.testing.assert_allclose(down["shear_stress"], -np.array(up["shear_stress"]), rtol=0, atol=1e-9 * scale)
    for key in ("normal_stress", "centre_cauchy_xx", "centre_cauchy_yy", "centre_cauchy_zz"):
        np.testing.assert_allclose(down[key], up[key], rtol=0, atol=1e-9 * scale, err_msg=key)
    assert np.max(np.abs(up["centre_cauchy_xx"])) > 1e-3 * scale  # the Poynting effect is there to see


def test_neo_hookean_normal_stress_difference_is_mu_gamma_squared_in_the_incompressible_limit():
    data = run("neo-hookean", "simple-shear", 0.4, K_over_mu=1e4)
    mu, gamma = 1.0, 0.4
    assert data["measured"]["normal_stress_difference"] == pytest.approx(mu * gamma**2, rel=1e-3)
    assert data["measured"]["G"] == pytest.approx(mu, rel=1e-3)
    N1 = np.array(data["curve"]["centre_cauchy_xx"]) - np.array(data["curve"]["centre_cauchy_yy"])
    np.testing.assert_allclose(N1, mu * np.array(data["curve"]["shear"]) ** 2, rtol=1e-3)


def _incompressible_neo_hookean(K_over_mu: float = 1e4):
    mu = 1.0
    K = K_over_mu * mu
    return make_material("neo-hookean", K - 2 * mu / 3, mu), mu


@pytest.mark.parametrize("stretch", [0.7, 1.2, 2.0, 3.0])
def test_planar_state_approaches_the_incompressible_closed_form_at_K_over_mu_1e4(stretch):
    material, mu = _incompressible_neo_hookean()
    state = planar(material, stretch)
    assert state.P[0, 0] == pytest.approx(mu * (stretch - stretch**-3), rel=1e-3)
    assert state.lateral_stretch == pytest.approx(1 / stretch, rel=1e-3)  # thickness t = 1/λ
    assert state.P[2, 2] == pytest.approx(0.0, abs=1e-9)


def test_planar_roller_block_approaches_the_incompressible_closed_form_at_K_over_mu_1e4():
    data = run("neo-hookean", "planar", 1.5, K_over_mu=1e4)
    lam = np.array(data["curve"]["stretch"])
    np.testing.assert_allclose(data["curve"]["stress"], lam - lam**-3, rtol=1e-3)


def test_simple_shear_oracle_of_neo_hookean_is_mu_times_b_minus_identity():
    material = make_material("neo-hookean", 5.0, 2.0)
    sigma = simple_shear(material, 0.3).cauchy
    expected = 2.0 * np.array([[0.09, 0.3, 0.0], [0.3, 0.0, 0.0], [0.0, 0.0, 0.0]])
    np.testing.assert_allclose(sigma, expected, atol=1e-12)


def test_planar_block_measures_the_planar_modulus_and_no_apparent_poisson_ratio_from_the_width():
    data = run("linear", "planar", 1.01)
    m = data["measured"]
    assert m["planar_modulus"] == pytest.approx(10.0 / (1 - 0.3**2), rel=1e-6)
    assert m["E"] == pytest.approx(10.0, rel=1e-6) and m["nu"] == pytest.approx(0.3, rel=1e-6)
    assert max(abs(x) for x in data["curve"]["transverse_strain"]) < 1e-12  # the width is held


BAD = [
    ({"test": {"kind": "simple-shear", "shear": 0.0}}, "test.shear must not be 0"),
    ({"test": {"kind": "simple-shear", "shear": 6.0}}, "test.shear must be >= -5 and <= 5"),
    ({"test": {"kind": "simple-shear", "shear": [0.1, 0.2]}}, "test.shear must be a single number"),
    ({"test": {"kind": "simple-shear", "shear": [0.2, 0.1], "protocol": "cyclic"}}, "test.shear must rise"),
    ({"test": {"kind": "simple-shear", "shear": [0.1, -0.2], "protocol": "cyclic"}}, "test.shear[1] must be > 0"),
    ({"test": {"kind": "simple-shear", "stretch": 1.2}}, "test.stretch applies to test.kind = 'uniaxial'"),
    ({"test": {"kind": "uniaxial", "stretch": 1.2, "shear": 0.1}}, "test.shear applies to test.kind = 'simple-shear'"),
    ({"test": {"kind": "simple-shear", "shear": 0.2, "grips": "roller"}}, "test.grips must be one of kinematic"),
    ({"test": {"kind": "planar", "stretch": 1.2, "grips": "clamped"}}, "test.grips must be one of roller"),
    ({"test": {"kind": "planar", "stretch": [1.2, 1.0]}}, "test.stretch must be a single number for kind = 'planar'"),
    ({"test": {"kind": "biaxial", "stretch": [1.2, 1.1], "protocol": "cyclic"}}, "test.protocol = 'cyclic' needs test.kind"),
    ({"test": {"kind": "simple-shear", "shear": 0.2}, "mesh": {"size": 1.0, "symmetry": "half"}},
     "mesh.symmetry must be 'none' for test.kind = 'simple-shear'"),
    ({"test": {"kind": "simple-shear", "shear": 0.2, "protocol": "creep", "force": 10.0, "ramp_time": 1.0,
               "hold_time": 10.0}, "effects": {"viscoelastic": {"tau": [1.0], "beta": [0.5]}}},
     "test.force needs test.kind = 'uniaxial'"),
    ({"specimen": {"shape": "planar-tension", "height": 10.0, "width": 50.0, "thickness": 1.0},
      "test": {"kind": "planar", "stretch": 1.2}}, "specimen.width must be >= 10 x specimen.height = 100 mm"),
    ({"specimen": {"shape": "planar-tension", "height": 10.0, "width": 100.0, "thickness": 12.0},
      "test": {"kind": "planar", "stretch": 1.2}}, "specimen.thickness must be <= specimen.height = 10 mm"),
    ({"specimen": {"shape": "planar-tension", "height": -1.0, "width": 100.0, "thickness": 1.0},
      "test": {"kind": "planar", "stretch": 1.2}}, "specimen.height must be > 0"),
    ({"specimen": {"shape": "shear", "length": 6.0, "gap": 4.0, "depth": 10.0},
      "test": {"kind": "simple-shear", "shear": 0.2}}, "specimen.length must be >= 2 x specimen.gap = 8 mm"),
    ({"specimen": {"shape": "double-lap", "length": 20.0, "gap": 4.0, "depth": 10.0, "plate_thickness": 0.0},
      "test": {"kind": "simple-shear", "shear": 0.2}}, "specimen.plate_thickness must be > 0"),
    ({"specimen": {"shape": "shear", "length": 20.0, "gap": 4.0, "depth": 10.0},
      "test": {"kind": "uniaxial", "stretch": 1.2}}, "test.kind must be one of simple-shear for specimen.shape = 'shear'"),
]


@pytest.mark.parametrize("override,message", BAD, ids=[m for _, m in BAD])
def test_bad_kind_and_shape_keys_are_scene_errors_naming_the_field_and_range(override, message):
    raw = block_scene("neo-hookean", {}) | {k: v for k, v in override.items() if k != "test" and k != "material"}
    raw["test"] = {"steps": 4, "grips": None} | override["test"]
    raw["test"] = {k: v for k, v in raw["test"].items() if v is not None}
    raw["material"] = raw["material"] | override.get("material", {})
    with pytest.raises(SceneError) as err:
        parse_scene(raw)
    assert message in str(err.value)


def test_cyclic_simple_shear_runs_fully_reversed_cycles():
    raw = block_scene("neo-hookean", {"kind": "simple-shear", "grips": "kinematic", "shear": [0.1, 0.2],
                                      "protocol": "cyclic", "steps": 4})
    data = result_to_dict(run_scene(parse_scene(raw)))
    gamma = np.array(data["curve"]["shear"])
    assert gamma.max() == pytest.approx(0.2) and gamma.min() == pytest.approx(-0.2)
    assert gamma[-1] == pytest.approx(0.0, abs=1e-15)
    assert data["reference"]["max_relative_error_shear"] < 1e-6


def test_every_registered_kind_names_its_load_key_and_axes():
    assert set(KINDS) == {"uniaxial", "biaxial", "planar", "simple-shear", "confined-compression", "torsion",
                          "inflation"}
    for kind in KINDS.values():
        assert kind.load_key in ("stretch", "shear", "twist") and kind.axes and kind.plot.series
        assert kind.rest == (1.0 if kind.load_key == "stretch" else 0.0)


LEN_DISPATCH = re.compile(r"len\(\s*[\w.\[\]]*(stretch|axes|targets)\s*\)")


def test_no_module_outside_the_kinds_dispatches_on_how_long_a_stretch_list_is():
    offenders = []
    for path in sorted(PACKAGE.rglob("*.py")):
        if "loading/kinds" in path.as_posix():
            continue
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if LEN_DISPATCH.search(line):
                offenders.append(f"{path.relative_to(PACKAGE)}:{n}: {line.strip()}")
    assert not offenders, "\n".join(offenders)


@pytest.mark.parametrize("plane", ["stress", "strain"])
def test_a_sheet_in_planar_tension_follows_its_plane_reduction_of_pure_shear(plane):
    raw = {"name": "sheet-planar", "specimen": {"shape": "sheet", "size": [4.0, 3.0], "thickness": 0.5, "plane": plane},
           "mesh": {"size": 1.0, "cell": "quad"}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
           "test": {"kind": "planar", "stretch": 1.3, "steps": 3}}
    data = result_to_dict(run_scene(parse_scene(raw)))
    assert data["converged"] and data["reference"]["max_relative_error_x"] < 1e-6
    if plane == "strain":  # F = diag(λ, 1, 1): nothing free
        assert data["reference"]["lateral_stretch"] == [1.0] * len(data["curve"]["stretch"])


def test_mullins_softening_shows_in_planar_tension_as_a_lower_unloading_path():
    raw = block_scene("neo-hookean", {"kind": "planar", "stretch": 1.5, "protocol": "load-unload", "steps": 4})
    raw["effects"] = {"mullins": {"r": 2.0, "m": 0.5}}
    data = result_to_dict(run_scene(parse_scene(raw)))
    assert data["converged"], data["failure"]
    lam, stress = np.array(data["curve"]["stretch"]), np.array(data["curve"]["stress"])
    peak = int(np.argmax(lam))
    up = np.interp(1.25, lam[:peak + 1], stress[:peak + 1])
    down = np.interp(1.25, lam[peak:][::-1], stress[peak:][::-1])
    assert down < 0.95 * up  # the softened unloading path lies below the virgin loading


@pytest.mark.parametrize("kind,values", [("uniaxial", (1.7,)), ("biaxial", (1.3, 0.8)), ("planar", (2.1,)),
                                         ("simple-shear", (0.6,))])
def test_every_kind_names_an_isochoric_path_through_its_target(kind, values):
    F = KINDS[kind].isochoric(values)
    assert np.linalg.det(F) == pytest.approx(1.0, rel=1e-12)
    assert F[0, 0] == pytest.approx(values[0]) if kind != "simple-shear" else F[0, 1] == pytest.approx(values[0])


def _plates(shape: str, extra: dict) -> dict:
    return {"name": shape, "specimen": {"shape": shape, "length": 8.0, "gap": 2.0, "depth": 4.0} | extra,
            "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.45},
            "test": {"kind": "simple-shear", "grips": "plates", "shear": 0.4, "steps": 3}}


def test_a_double_lap_sandwich_shears_each_layer_as_a_single_lap_specimen():
    single = result_to_dict(run_scene(parse_scene(_plates("shear", {}))))
    double = result_to_dict(run_scene(parse_scene(_plates("double-lap", {"plate_thickness": 1.0}))))
    assert double["converged"] and single["converged"]
    # the central plate carries both layers over twice the area: the same nominal stress, shear and gauge
    for key in ("shear_stress", "shear_gauge"):
        np.testing.assert_allclose(double["curve"][key], single["curve"][key], rtol=1e-7, err_msg=key)
    np.testing.assert_allclose(double["curve"]["shear_force"], 2 * np.array(single["curve"]["shear_force"]), rtol=1e-7)
    scale = max(abs(f) for f in double["curve"]["shear_force"])
    assert max(abs(f) for f in double["curve"]["normal_force"]) < 1e-8 * scale  # the layers' normal forces cancel
    assert max(abs(f) for f in single["curve"]["normal_force"]) > 1e-3 * scale  # a single lap pulls on its plate
    assert double["measured"]["G"] == pytest.approx(single["measured"]["G"], rel=1e-7)


@pytest.mark.skipif("gent" not in MODELS, reason="needs the Gent model")
@pytest.mark.parametrize("test,where", [({"kind": "simple-shear", "shear": 4.0}, "at shear 3.4641"),
                                        ({"kind": "planar", "stretch": 4.5}, "at stretch 3.73205")])
def test_a_gent_card_is_refused_past_its_locking_limit_on_the_kind_s_isochoric_path(test, where):
    # simple shear: Ī1 − 3 = γ² = Jm; pure shear: λ² + λ⁻² − 2 = Jm (Jm = 12)
    raw = block_scene("gent", test, {"mu": 0.5, "Jm": 12.0, "K": 20.0})
    with pytest.raises(SceneError) as err:
        parse_scene(raw)
    assert where in str(err.value) and f"test.{'shear' if 'shear' in test else 'stretch'}:" in str(err.value)
