"""The incompressible card's stand-in bulk modulus: stated, and chosen with [model] K_over_mu."""

import tomllib
from pathlib import Path

import pytest

from vlab.fields import SceneError
from vlab.identify.fitfile import parse_fit
from vlab.identify.fitting import fit_any

TRELOAR = Path(__file__).resolve().parents[1] / "specimens" / "treloar1944"


def _spec(model: dict):
    return parse_fit({"name": "k", "model": model, "options": {"starts": 2},
                      "data": [{"file": "uniaxial.csv", "kind": "uniaxial",
                                "columns": {"stretch": "stretch", "stress": "nominal_stress_MPa"}}]}, TRELOAR)


def test_the_default_card_states_k_equal_to_1000_mu0_in_fit_json_the_note_and_the_card_comment():
    d = fit_any(_spec({"name": "neo-hookean"})).data
    mu0 = d["model"]["mu0"]
    assert d["model"]["K_over_mu"] == 1000.0 and d["model"]["card_K"] == pytest.approx(1000 * mu0)
    assert d["card"]["material"]["K"] == pytest.approx(1000 * mu0, rel=1e-5)
    assert "K = 1000 mu0" in d["card"]["note"] and "nu = 0.4995" in d["card"]["note"]
    assert d["card"]["toml"].startswith("# incompressible fit: K = 1000 mu0")
    assert tomllib.loads(d["card"]["toml"])["material"]["K"] == d["card"]["material"]["K"]


def test_k_over_mu_sets_the_cards_bulk_modulus():
    d = fit_any(_spec({"name": "neo-hookean", "K_over_mu": 200.0})).data
    assert d["card"]["material"]["K"] == pytest.approx(200 * d["model"]["mu0"], rel=1e-5)
    assert d["model"]["K_over_mu"] == 200.0 and "K = 200 mu0" in d["card"]["note"]


@pytest.mark.parametrize("model,message", [
    ({"name": "neo-hookean", "K_over_mu": 5.0}, r"model.K_over_mu must be >= 10 and <= 1e\+08"),
    ({"name": "neo-hookean", "K_over_mu": "big"}, r"model.K_over_mu must be a number"),
    ({"name": "neo-hookean", "K": 50.0, "K_over_mu": 100.0}, r"model.K_over_mu is the card's stand-in K"),
    ({"name": "neo-hookean", "fit_K": True, "K_over_mu": 100.0}, r"model.K_over_mu is the card's stand-in K"),
])
def test_a_bad_k_over_mu_is_refused_naming_the_key_and_range(model, message):
    with pytest.raises(SceneError, match=message):
        _spec(model)
