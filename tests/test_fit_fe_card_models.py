"""FE in the loop with the FE library's card models (issue #18): Mooney–Rivlin sensitivities and
the issue's target, a two-parameter Mooney–Rivlin recovered from a dumb-bell curve."""

import tomllib

import numpy as np
import pytest

from vlab.identify.fe_sensitivity import simulate

BLOCK = '''name = "fe-block-mr"
[specimen]
shape = "block"
size = [12.0, 4.0, 4.0]
[mesh]
size = 2.0
order = 1
cell = "hex"
[material]
model = "mooney-rivlin"
C10 = 0.2
C01 = 0.05
K = 4.0
[test]
kind = "uniaxial"
grips = "clamped"
stretch = 1.5
steps = 4
'''

DUMBBELL = '''name = "fe-dumbbell-mr"
[specimen]
shape = "dogbone"
standard = "ISO 37 2"
[mesh]
size = 2.0
order = 1
cell = "hex"
[material]
model = "mooney-rivlin"
C10 = 0.2
C01 = 0.05
K = 4.0
[test]
kind = "uniaxial"
stretch = 1.6
steps = 8
'''


def _fe(tmp_path, text, params):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    raw = tomllib.loads(text)
    return {"scene_path": str(path), "scene_raw": raw, "parameters": params, "model": "mooney-rivlin",
            "volumetric": None}


def test_mooney_rivlin_sensitivities_match_whole_test_differences(tmp_path):
    fe = _fe(tmp_path, BLOCK, ("C10", "C01", "K"))
    base = {"C10": 0.2, "C01": 0.05, "K": 4.0}
    s = simulate(fe, base)
    for j, p in enumerate(fe["parameters"]):
        h = 1e-5
        a, b = simulate(fe, base | {p: base[p] + h}), simulate(fe, base | {p: base[p] - h})
        dF, de = (a.force[:, 0] - b.force[:, 0]) / (2 * h), (a.strain[:, 0] - b.strain[:, 0]) / (2 * h)
        assert np.allclose(s.dforce[:, 0, j], dF, rtol=1e-5, atol=1e-6 * np.max(np.abs(dF))), p
        assert np.allclose(s.dstrain[:, 0, j], de, rtol=1e-4, atol=1e-5 * np.max(np.abs(de)) + 1e-12), p


@pytest.mark.slow
def test_two_parameter_mooney_rivlin_comes_back_from_a_noisy_dumbbell_curve_within_two_standard_errors(tmp_path):
    """The issue's target: 1 % noise, start 50 % off, at most 15 whole-test solves (5 seeds)."""
    from vlab.identify.fe_loop import fit_specimen
    from vlab.identify.fitfile import load_fit

    true = {"C10": 0.2, "C01": 0.05}
    s = simulate(_fe(tmp_path, DUMBBELL, ("C10",)), true | {"K": 4.0})
    within = 0
    for seed in range(5):
        rng = np.random.default_rng(seed)
        force = s.force[:, 0] * (1 + 0.01 * rng.standard_normal(len(s.force[:, 0])))
        (tmp_path / "r.csv").write_text("strain,force\n" + "".join(f"{e:.17g},{f:.17g}\n" for e, f in zip(s.strain[:, 0], force)))
        (tmp_path / "fit.toml").write_text('[model]\nname = "mooney-rivlin"\n[[data]]\nfile = "r.csv"\nkind = "specimen"\n'
                                           '[fe]\nscene = "scene.toml"\nparameters = ["C10", "C01"]\n'
                                           'start = { C10 = 0.3, C01 = 0.075 }\nmax_solves = 15\ncache = false\n')
        d = fit_specimen(load_fit(tmp_path / "fit.toml")).data
        assert d["converged"] and d["fe"]["solves"] <= 15, d["reason"]
        z = [abs(d["parameters"][n] - true[n]) / d["uncertainty"][n]["standard_error"] for n in true]
        within += max(z) <= 2.0
        assert d["card"]["material"]["model"] == "mooney-rivlin"
    assert within >= 4
