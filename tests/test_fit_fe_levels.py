"""FE in the loop for every model of the library: ∂P/∂p by the complex step on the principal
stresses, and sensitivities back-substituted with the factorization the step already has."""

import tomllib

import numpy as np
import pytest

from vlab.identify.fe_sensitivity import simulate
from vlab.identify.fe_stress import card_table, flat_constants, principal_stress_of, stress_derivatives
from vlab.materials.card import build_material, parse_material

CARDS = [
    {"model": "neo-hookean", "mu": 0.4, "K": 3.0},
    {"model": "mooney-rivlin", "C10": 0.2, "C01": 0.05, "K": 4.0},
    {"model": "yeoh", "C10": 0.2, "C20": -0.01, "C30": 0.002, "K": 4.0},
    {"model": "gent", "mu": 0.4, "Jm": 20.0, "K": 4.0, "volumetric": "log"},
    {"model": "arruda-boyce", "mu": 0.4, "lambda_m": 3.0, "K": 4.0, "volumetric": "simo-taylor"},
    {"model": "ogden", "mu": [0.3, 0.01, -0.02], "alpha": [1.5, 5.0, -2.0], "K": 10.0},
]


def _deformations(n=40):
    rng = np.random.default_rng(0)
    F = np.eye(3)[:, :, None] + 0.3 * rng.standard_normal((3, 3, n))
    F = F[:, :, np.linalg.det(np.moveaxis(F, -1, 0)) > 0.2]
    return np.concatenate([F, np.repeat(np.diag([1.3, 0.9, 0.9])[:, :, None], 2, axis=2)], axis=2)  # coalescent


def _stress(model, values, volumetric, F):
    card = card_table(values) | {"model": model} | ({"volumetric": volumetric} if volumetric else {})
    return build_material(parse_material(card)).stress(F)


@pytest.mark.parametrize("card", CARDS, ids=lambda c: c["model"])
def test_the_identification_librarys_principal_stress_is_the_fe_librarys_stress(card):
    spec, F = parse_material(card), _deformations()
    P = build_material(spec).stress(F)
    Q = principal_stress_of(F, spec.model, flat_constants(spec), spec.volumetric)
    assert np.max(np.abs(P - Q)) <= 1e-12 * np.max(np.abs(P))


@pytest.mark.parametrize("card", CARDS, ids=lambda c: c["model"])
def test_every_constants_stress_derivative_matches_central_differences_of_the_fe_librarys_stress(card):
    spec, F = parse_material(card), _deformations()
    v = flat_constants(spec)
    d = stress_derivatives(F, spec.model, v, list(v), spec.volumetric)
    for p in v:
        h = 1e-6 * max(abs(v[p]), 1e-3)
        fd = (_stress(spec.model, v | {p: v[p] + h}, spec.volumetric, F)
              - _stress(spec.model, v | {p: v[p] - h}, spec.volumetric, F)) / (2 * h)
        assert np.max(np.abs(fd - d[p])) <= 1e-7 * np.max(np.abs(d[p])), p


OGDEN_BLOCK = '''name = "fe-block-ogden"
[specimen]
shape = "block"
size = [12.0, 4.0, 4.0]
[mesh]
size = 2.0
order = 1
cell = "hex"
[material]
model = "ogden"
mu = [0.3, 0.02]
alpha = [1.8, 5.0]
K = 4.0
[test]
kind = "uniaxial"
grips = "clamped"
stretch = 1.5
steps = 4
'''


def _fe(tmp_path, text, model, names):
    (tmp_path / "scene.toml").write_text(text)
    return {"scene_path": str(tmp_path / "scene.toml"), "scene_raw": tomllib.loads(text), "parameters": names,
            "model": model, "volumetric": None}


def test_ogden_sensitivities_of_every_mu_alpha_and_k_match_whole_test_differences(tmp_path):
    names = ("mu[0]", "mu[1]", "alpha[0]", "alpha[1]", "K")
    fe = _fe(tmp_path, OGDEN_BLOCK, "ogden", names)
    base = {"mu[0]": 0.3, "mu[1]": 0.02, "alpha[0]": 1.8, "alpha[1]": 5.0, "K": 4.0}
    s = simulate(fe, base)
    for j, p in enumerate(names):
        h = 1e-6 * abs(base[p])
        a, b = simulate(fe, base | {p: base[p] + h}), simulate(fe, base | {p: base[p] - h})
        dF, de = (a.force - b.force) / (2 * h), (a.strain - b.strain) / (2 * h)
        assert np.max(np.abs(s.dforce[:, :, j] - dF)) <= 1e-5 * np.max(np.abs(dF)), p
        assert np.max(np.abs(s.dstrain[:, :, j] - de)) <= 1e-5 * np.max(np.abs(de)), p


@pytest.mark.parametrize("model,material,names", [
    ("gent", 'model = "gent"\nmu = 0.4\nJm = 6.0\nK = 4.0\n', ("mu", "Jm")),
    ("arruda-boyce", 'model = "arruda-boyce"\nmu = 0.4\nlambda_m = 2.5\nK = 4.0\n', ("lambda_m", "K")),
])
def test_gent_jm_and_arruda_boyce_lambda_m_sensitivities_match_whole_test_differences(tmp_path, model, material, names):
    text = OGDEN_BLOCK.replace('model = "ogden"\nmu = [0.3, 0.02]\nalpha = [1.8, 5.0]\nK = 4.0\n', material)
    fe = _fe(tmp_path, text, model, names)
    base = {k: v for k, v in flat_constants(parse_material(tomllib.loads(text)["material"])).items()}
    s = simulate(fe, base)
    for j, p in enumerate(names):
        h = 1e-6 * abs(base[p])
        a, b = simulate(fe, base | {p: base[p] + h}), simulate(fe, base | {p: base[p] - h})
        dF = (a.force - b.force) / (2 * h)
        assert np.max(np.abs(s.dforce[:, :, j] - dF)) <= 1e-5 * np.max(np.abs(dF)), p


def test_sensitivities_back_substitute_with_the_monitors_factor_and_factorize_nothing(tmp_path):
    """Before: K assembled and K_ff factorized once more per recorded level; now none."""
    names = ("mu[0]", "alpha[0]")
    fe = _fe(tmp_path, OGDEN_BLOCK, "ogden", names)
    base = {"mu[0]": 0.3, "mu[1]": 0.02, "alpha[0]": 1.8, "alpha[1]": 5.0, "K": 4.0}
    reused, own = simulate(fe, base), simulate(fe, base, refactorize=True)
    c, k = reused.counts, own.counts
    assert c["sensitivity_factorizations"] == 0 and c["levels_with_the_monitors_factor"] == c["levels"]
    assert c["sensitivity_solves"] == len(names) * c["levels"]
    assert k["total_factorizations"] == c["total_factorizations"] + c["levels"]
    np.testing.assert_allclose(reused.dforce, own.dforce, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(reused.dstrain, own.dstrain, rtol=1e-9, atol=1e-14)


def test_a_two_term_ogden_block_curve_gives_back_mu_and_alpha_through_vlabs_own_test(tmp_path):
    from vlab.identify.fe_loop import fit_specimen
    from vlab.identify.fitfile import load_fit

    fe = _fe(tmp_path, OGDEN_BLOCK, "ogden", ("mu[0]",))
    true = {"mu[0]": 0.3, "mu[1]": 0.02, "alpha[0]": 1.8, "alpha[1]": 5.0, "K": 4.0}
    s = simulate(fe, true)
    (tmp_path / "r.csv").write_text("strain,force\n" + "".join(f"{e:.17g},{f:.17g}\n"
                                                                for e, f in zip(s.strain[:, 0], s.force[:, 0])))
    (tmp_path / "fit.toml").write_text('[model]\nname = "ogden"\nterms = 2\n[[data]]\nfile = "r.csv"\nkind = "specimen"\n'
                                       '[fe]\nscene = "scene.toml"\nparameters = ["mu[0]", "alpha"]\n'
                                       'start = { "mu[0]" = 0.2, alpha = [1.2, 6.0] }\nmax_solves = 15\ncache = false\n')
    d = fit_specimen(load_fit(tmp_path / "fit.toml")).data
    assert d["converged"] and d["fe"]["solves"] <= 8 and "matched" in d["reason"]
    assert list(d["parameters"]) == ["mu[0]", "alpha[0]", "alpha[1]"]
    for n in d["parameters"]:  # noise-free readings: the constants come back to the solver's tolerance
        assert d["parameters"][n] == pytest.approx(true[n], rel=1e-4), n
    assert d["card"]["material"]["alpha"] == pytest.approx([1.8, 5.0], rel=1e-4)
    assert d["card"]["note"] == "K held at the scene's value"


@pytest.mark.parametrize("fe_table,message", [
    ('parameters = ["beta"]', r"fe.parameters\[\] must be one of mu\[0\], mu\[1\], alpha\[0\], alpha\[1\], K"),
    ('parameters = ["alpha"]\nstart = { alpha = [1.0] }', r"fe.start.alpha must list 2 values \(one per term\), got 1"),
    ('parameters = ["alpha[0]"]\nstart = { "alpha[0]" = -1.0 }', r"fe.start: .* is not admissible"),
    ('parameters = ["K", "K"]', r"fe.parameters names a constant twice"),
])
def test_bad_ogden_fe_parameters_and_starts_are_refused_naming_the_key(tmp_path, fe_table, message):
    from vlab.fields import SceneError
    from vlab.identify.fitfile import load_fit

    (tmp_path / "scene.toml").write_text(OGDEN_BLOCK)
    (tmp_path / "r.csv").write_text("strain,force\n0.1,1\n0.2,2\n")
    (tmp_path / "fit.toml").write_text('[model]\nname = "ogden"\nterms = 2\n[[data]]\nfile = "r.csv"\nkind = "specimen"\n'
                                       f'[fe]\nscene = "scene.toml"\n{fe_table}\n')
    with pytest.raises(SceneError, match=message):
        load_fit(tmp_path / "fit.toml")
