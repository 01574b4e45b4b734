"""Bad material cards are refused with the field and its allowed range; the CLI exits 2 and
writes nothing."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

import numpy as np

from rubber_cards import card
from scenes import scene_dict
from vlab.cli import app
from vlab.fields import SceneError
from vlab.scene import parse_scene


def refused(material: dict, **test) -> str:
    raw = scene_dict(test=test or {})
    raw["material"] = material
    with pytest.raises(SceneError) as exc:
        parse_scene(raw)
    return str(exc.value)


@pytest.mark.parametrize("material, fragments", [
    (card("ogden") | {"alpha": [1.3, 5.0]}, ["material: the lists mu, alpha need equal lengths",
                                             "material.mu has 3", "material.alpha has 2"]),
    (card("ogden") | {"alpha": [1.3, 0.0, -2.0]}, ["material.alpha[1] must be != 0"]),
    (card("ogden") | {"mu": [-0.63, 0.0012, -0.01]}, ["initial shear modulus mu0 = Σₚ μₚ must be > 0",
                                                     "material.mu and material.alpha", "got -0.6388"]),
    (card("mooney-rivlin") | {"C10": -0.1, "C01": 0.05}, ["mu0 = 2 (C10 + C01) must be > 0", "got -0.1"]),
    (card("yeoh") | {"C10": 0.0}, ["mu0 = 2 C10 must be > 0"]),
    (card("gent") | {"Jm": 0.0}, ["material.Jm must be > 0"]),
    (card("gent") | {"mu": -1.0}, ["material.mu must be > 0 (MPa, shear modulus μ)"]),
    (card("arruda-boyce") | {"lambda_m": 1.0}, ["material.lambda_m must be > 1"]),
    (card("mooney-rivlin") | {"C02": 0.1}, ["unknown key 'C02' in [material]", "allowed:"]),
    (card("yeoh") | {"E": 3.0}, ["unknown key 'E' in [material]"]),
    (card("gent") | {"D1": 0.1}, ["needs exactly one of material.K", "got K, D1"]),
    ({"model": "gent", "mu": 0.5, "Jm": 12.0}, ["needs exactly one of material.K (MPa), material.D1",
                                                "got none"]),
    (card("gent", K=-3.0), ["material.K must be > 0 (MPa, bulk modulus)"]),
    (card("gent", D1=0.0), ["material.D1 must be > 0"]),
    (card("yeoh", nu=0.5), ["material.nu must be > -1 and < 0.5"]),
    (card("yeoh") | {"volumetric": "cubic"}, ["material.volumetric must be one of quadratic, log, simo-taylor"]),
    ({"model": "mooney-rivlin", "C10": 0.3, "K": 5.0}, ["missing required key material.C01"]),
    (card("ogden") | {"mu": "0.6"}, ["material.mu must be a list of numbers"]),
])
def test_a_bad_card_is_refused_naming_the_field_and_the_range(material, fragments):
    msg = refused(material)
    for fragment in fragments:
        assert fragment in msg, msg


@pytest.mark.parametrize("stretch, Jm, path", [(4.5, 12.0, lambda l: l**2 + 2 / l),
                                                (0.25, 5.0, lambda l: l**2 + 2 / l),
                                                ([2.8, 2.8], 12.0, lambda l: 2 * l**2 + l**-4)])
def test_a_gent_test_past_the_locking_stretch_is_refused_naming_the_limit(stretch, Jm, path):
    gent = card("gent") | {"Jm": Jm}
    msg = refused(gent, stretch=stretch, kind="biaxial" if isinstance(stretch, list) else "uniaxial")
    assert f"Gent chains lock at Ī1 − 3 = Jm = {Jm:g}" in msg and "material.Jm" in msg
    limit = float(msg.split("reaches it at stretch ")[1].split(",")[0])
    assert path(limit) - 3 == pytest.approx(Jm, rel=2e-5)  # the incompressible path's Ī₁ − 3 = Jm
    raw = scene_dict(test={"stretch": 0.99 * limit if limit > 1 else 1.01 * limit})
    raw["material"] = gent
    parse_scene(raw)  # inside the limit: accepted


def test_the_cli_exits_2_on_a_bad_card_and_writes_nothing(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('name = "bad"\n[specimen]\nshape = "block"\nsize = [10.0, 10.0, 10.0]\n[mesh]\nsize = 5.0\n'
                    '[material]\nmodel = "ogden"\nmu = [0.5, 0.1]\nalpha = [2.0]\nK = 100.0\n'
                    '[test]\nkind = "uniaxial"\nstretch = 1.2\n')
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["run", str(path), "--out", str(out), "-q"])
    assert res.exit_code == 2 and "material.alpha has 1" in res.output
    assert not out.exists()


def test_the_lame_models_keep_their_grammar_and_refuse_card_keys():
    raw = scene_dict(material={"model": "neo-hookean", "E": 10.0, "nu": 0.3, "C10": 1.0})
    with pytest.raises(SceneError, match="unknown key 'C10' in \\[material\\]"):
        parse_scene(raw)


def test_nu_with_the_card_gives_the_bulk_modulus_of_mu0():
    raw = scene_dict()
    raw["material"] = card("mooney-rivlin", nu=0.45)
    m = parse_scene(raw).material
    assert m.moduli.mu == pytest.approx(0.76) and m.moduli.nu == pytest.approx(0.45)
    assert m.moduli.K == pytest.approx(2 * 0.76 * 1.45 / (3 * 0.1))


def test_every_layer_reads_the_one_model_registry():
    from vlab.effects import EFFECTS
    from vlab.materials import CARD_MODELS, LAME_MODELS, MODELS as REGISTRY
    from vlab.scene import MODELS as SCENE_MODELS

    assert SCENE_MODELS == tuple(REGISTRY)
    assert set(CARD_MODELS) == {"mooney-rivlin", "yeoh", "ogden", "gent", "arruda-boyce"}
    assert EFFECTS["viscoelastic"].models == ("neo-hookean",) + CARD_MODELS
    assert EFFECTS["mullins"].models == LAME_MODELS + CARD_MODELS
    assert EFFECTS["plasticity"].models == LAME_MODELS
    for name in CARD_MODELS:
        entry = REGISTRY[name]
        assert entry.split is not None and entry.isochoric and entry.continuum and entry.formula
        assert all(c.unit in ("MPa", "-") and c.doc for c in entry.constants)


@pytest.mark.parametrize("model", ["stvk", "stvk-volumetric"])
def test_the_mixed_formulation_is_refused_for_a_model_without_a_split(model):
    raw = scene_dict(material={"model": model, "E": 10.0, "nu": 0.3}, mesh={"formulation": "mixed"})
    with pytest.raises(SceneError, match="allowed with 'mixed': linear, neo-hookean, mooney-rivlin, yeoh, "
                                         "ogden, gent, arruda-boyce"):
        parse_scene(raw)


def test_a_card_whose_initial_tangent_is_not_positive_definite_is_refused_with_the_eigenvalue():
    from vlab.materials.card import _check_initial_tangent
    from vlab.materials.registry import MODELS as REGISTRY

    class Unstable:  # a law whose A(I) has a negative bulk response: A = μ(δδ + δδᵀ) − 2 I⊗I
        def tangent(self, F):
            I = np.eye(3)
            A = (np.einsum("ik,jl->ijkl", I, I) + np.einsum("il,jk->ijkl", I, I)
                 - 2.0 * np.einsum("ij,kl->ijkl", I, I))
            return A[..., None]

    with pytest.raises(SceneError, match="initial tangent is not positive definite on symmetric strains "
                                         r"\(smallest eigenvalue -4 MPa"):
        _check_initial_tangent(Unstable(), "material", REGISTRY["mooney-rivlin"])
