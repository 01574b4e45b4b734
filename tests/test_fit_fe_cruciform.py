"""FE in the loop on a cruciform: both arm forces and both extensometers fitted at once."""

import tomllib

import numpy as np
import pytest

from vlab.fields import SceneError
from vlab.identify.fe_sensitivity import simulate

CRUCIFORM = '''name = "fe-cruciform"
[specimen]
shape = "cruciform"
arm_width = 10.0
arm_length = 10.0
gauge_region = 6.0
fillet_radius = 2.0
thickness = 2.0
grip_length = 4.0
[mesh]
size = 2.5
cell = "hex"
symmetry = "eighth"
[material]
model = "mooney-rivlin"
C10 = 0.2
C01 = 0.05
K = 4.0
[test]
kind = "biaxial"
stretch = [1.3, 1.15]
steps = 4
'''
TRUE = {"C10": 0.2, "C01": 0.05, "K": 4.0}


def _readings(tmp_path, noise=0.005, seed=1):
    (tmp_path / "cruciform.toml").write_text(CRUCIFORM)
    fe = {"scene_path": str(tmp_path / "cruciform.toml"), "scene_raw": tomllib.loads(CRUCIFORM),
          "parameters": ("C10",), "model": "mooney-rivlin", "volumetric": None, "axes": (0, 1)}
    s = simulate(fe, TRUE)
    rng = np.random.default_rng(seed)
    F = s.force * (1 + noise * rng.standard_normal(s.force.shape))
    rows = "".join(f"{e1:.17g},{f1:.17g},{e2:.17g},{f2:.17g}\n" for e1, f1, e2, f2 in
                   zip(s.strain[:, 0], F[:, 0], s.strain[:, 1], F[:, 1]))
    (tmp_path / "arms.csv").write_text("ex,Fx,ey,Fy\n" + rows)
    return s


FIT = '''[model]
name = "mooney-rivlin"
[[data]]
file = "arms.csv"
kind = "specimen"
columns = {{ strain = "ex", force = "Fx", strain2 = "ey", force2 = "Fy" }}
[fe]
scene = "{scene}"
parameters = ["C10", "C01"]
start = {{ C10 = 0.3, C01 = 0.075 }}
max_solves = 15
cache = false
'''


def test_a_cruciforms_two_arm_forces_give_back_both_mooney_rivlin_constants(tmp_path):
    from vlab.identify.fe_loop import fit_specimen
    from vlab.identify.fitfile import load_fit

    s = _readings(tmp_path)
    assert np.all(np.diff(s.strain[:, 1]) > 0) and s.force.shape[1] == 2
    (tmp_path / "fit.toml").write_text(FIT.format(scene="cruciform.toml"))
    d = fit_specimen(load_fit(tmp_path / "fit.toml")).data
    assert d["converged"] and d["fe"]["solves"] <= 15 and d["fe"]["axes"] == ["x", "y"]
    for n in ("C10", "C01"):
        assert abs(d["parameters"][n] - TRUE[n]) <= 3 * d["uncertainty"][n]["standard_error"], n
    assert d["datasets"][0]["points"] == len(s.strain)
    assert d["fe"]["homogeneous_fit"]["kind"] == "biaxial"
    assert d["fe"]["counts"]["sensitivity_factorizations"] == 0
    # stability is judged over the readings' stretches (1 + the largest arm strain), not assumed
    top = 1.0 + float(np.max(s.strain))
    for kind in ("uniaxial", "equibiaxial"):
        assert d["stability"]["kinds"][kind]["fitted_range"][1] == pytest.approx(top), kind
    assert "fitted_range" not in d["stability"]["kinds"]["planar"]
    assert d["stability"]["stable_over_all_fitted_ranges"] is True and "equibiaxial" in d["stability"]["basis"]


def test_second_axis_columns_on_a_one_axis_scene_are_refused(tmp_path):
    from vlab.identify.fitfile import load_fit

    _readings(tmp_path)
    (tmp_path / "bar.toml").write_text(_bar())
    (tmp_path / "fit.toml").write_text(FIT.format(scene="bar.toml"))
    with pytest.raises(SceneError, match=r"data\[0\]\.columns\.strain2: a specimen data set of fe.scene's test.kind 'uniaxial' has no column 'strain2'"):
        load_fit(tmp_path / "fit.toml")


def _bar() -> str:
    return ('name = "bar"\n[specimen]\nshape = "block"\nsize = [12.0, 4.0, 4.0]\n[mesh]\nsize = 2.0\ncell = "hex"\n'
            '[material]\nmodel = "mooney-rivlin"\nC10 = 0.2\nC01 = 0.05\nK = 4.0\n'
            '[test]\nkind = "uniaxial"\ngrips = "clamped"\nstretch = 1.3\nsteps = 4\n')


def test_a_second_strain_column_without_its_force_is_refused_naming_the_file(tmp_path):
    from vlab.identify.fitfile import load_fit

    _readings(tmp_path)
    (tmp_path / "fit.toml").write_text(FIT.format(scene="cruciform.toml").replace(', force2 = "Fy"', ""))
    with pytest.raises(SceneError, match=r"data\[0\]\.columns\.strain2 needs its reading too: columns.force2"):
        load_fit(tmp_path / "fit.toml")
