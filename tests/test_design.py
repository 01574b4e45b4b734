"""`vlab design`: Fisher-information test design (vlab.identify.design) against closed forms and
the known identifiability facts of Mooney–Rivlin and Ogden."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

sys.path.insert(0, str(Path(__file__).parent))
from fit_helpers import GRIDS  # noqa: E402

from vlab.cli import app  # noqa: E402
from vlab.identify.design import PlannedTest, assess, combinations, plan_rows  # noqa: E402
from vlab.identify.laws import law_for  # noqa: E402
from vlab.identify.states import Constitutive, response  # noqa: E402

MR = Constitutive(law_for("mooney-rivlin"))
MR_CARD = np.array([0.3, 0.05])
OGDEN3 = Constitutive(law_for("ogden", 3))
OGDEN3_CARD = np.array([0.63, 0.0012, -0.01, 1.3, 5.0, -2.0])  # Ogden 1972's Treloar constants (MPa)


def _x(model, card):
    return np.linalg.solve(model.transform, card)


def _plans(*kinds):
    return [PlannedTest(k, float(GRIDS[k][0]), float(GRIDS[k][-1]), 20) for k in kinds]


def _by_label(entries):
    return {tuple(t["kind"] for t in e["tests"]): e for e in entries}


def test_neo_hookean_uniaxial_standard_error_is_the_closed_form():
    """Absolute residuals, P = μ (λ − λ⁻²): SE(μ) = s / √Σ (λ_k − λ_k⁻²)²."""
    nh = Constitutive(law_for("neo-hookean"))
    plan = PlannedTest("uniaxial", 1.1, 3.0, 15)
    J = plan_rows(nh, np.array([0.4]), plan, relative=False)
    a = np.linspace(1.1, 3.0, 15)
    got = assess(J, 0.02, [0.4], ["mu"])["standard_errors"]["mu"]
    assert got == pytest.approx(0.02 / np.sqrt(np.sum((a - a ** -2) ** 2)), rel=1e-12)


def test_mooney_rivlin_pure_shear_alone_cannot_separate_c10_and_c01():
    out = _by_label(combinations(MR, _x(MR, MR_CARD), _plans("uniaxial", "equibiaxial", "planar"), 0.01, True, 2))
    planar = out[("planar",)]
    assert planar["verdict"] == "not determined"
    assert planar["standard_errors"] == {"C10": None, "C01": None} and planar["D"] is None
    # I1 = I2 in pure shear: only C10 + C01 is seen, so δC10 = +1, δC01 = −1 changes nothing
    assert "C10, C01 not determined" in planar["reason"] and "+1·δC10 -1·δC01" in planar["reason"]
    for other in ("uniaxial", "equibiaxial"):
        both = out[tuple(sorted(("planar", other), key=("uniaxial", "equibiaxial", "planar").index))]
        assert both["verdict"] == "well-posed"
        assert all(0 < v < 0.05 * c for v, c in zip(both["standard_errors"].values(), MR_CARD))
    ranked = combinations(MR, _x(MR, MR_CARD), _plans("uniaxial", "equibiaxial", "planar"), 0.01, True, 2)
    assert ranked[-1]["tests"][0]["kind"] == "planar"  # the undetermined one is ranked last


def test_ogden3_uniaxial_only_is_ill_posed_and_equibiaxial_cures_most_of_it():
    x = _x(OGDEN3, OGDEN3_CARD)
    out = _by_label(combinations(OGDEN3, x, _plans("uniaxial", "equibiaxial"), 0.01, True, 2))
    uni, both = out[("uniaxial",)], out[("uniaxial", "equibiaxial")]
    assert uni["verdict"] == "ill-conditioned" and uni["worst_correlation"] > 0.999
    assert max(uni["relative_errors"].values()) > 10  # > 1000 % at 1 % noise
    assert max(both["relative_errors"].values()) < max(uni["relative_errors"].values()) / 10
    assert both["D"] < uni["D"] / 5


def test_more_tests_never_lose_information():
    """F grows with every test added, so D and every standard error can only fall."""
    x = _x(OGDEN3, OGDEN3_CARD)
    out = _by_label(combinations(OGDEN3, x, _plans("uniaxial", "equibiaxial", "planar", "simple-shear"),
                                 0.01, True, 4))
    for key, e in out.items():
        for sub in (k for k in out if set(k) < set(key)):
            if out[sub]["D"] is not None:
                assert e["D"] <= out[sub]["D"] * (1 + 1e-9)


def _fit_file(tmp_path: Path, kind: str = "planar", model: str = "mooney-rivlin", noise: float = 0.01) -> Path:
    a = GRIDS[kind]
    m = Constitutive(law_for("mooney-rivlin"))
    y = np.real(response(m, _x(m, MR_CARD)[None], kind, a))[0]
    y = y * (1 + noise * np.random.default_rng(3).standard_normal(len(y)))
    (tmp_path / "d.csv").write_text("stretch,stress\n" + "".join(f"{float(u)!r},{float(v)!r}\n" for u, v in zip(a, y)))
    f = tmp_path / "fit.toml"
    f.write_text(f'name = "d"\n[model]\nname = "{model}"\n[[data]]\nfile = "d.csv"\nkind = "{kind}"\n'
                 "[options]\nstarts = 3\n")
    return f


def test_cli_planar_data_next_test_determines_both_constants(tmp_path):
    f = _fit_file(tmp_path)
    # planar data alone leave the fit anywhere in its C10 − C01 valley: design around the expected card
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out"), "--noise", "0.01",
                                   "--candidates", "uniaxial,equibiaxial,planar", "--expect", "C10=0.3,C01=0.05"])
    assert res.exit_code == 0, res.output
    d = json.loads((tmp_path / "out" / "design.json").read_text())
    assert d["parameters"] == {"C10": pytest.approx(0.3), "C01": pytest.approx(0.05)}
    assert d["present_data"]["verdict"] == "not determined"
    best = d["next"][0]
    assert best["tests"][0]["kind"] in ("uniaxial", "equibiaxial")
    assert best["now_determined"] == ["C10", "C01"] and best["verdict"] == "well-posed"
    assert d["answer"].startswith(f"add {best['tests'][0]['kind']}") and "determines C10, C01" in d["answer"]
    assert d["candidates"][0]["D"] is not None and (tmp_path / "out" / "index.html").is_file()


@pytest.mark.parametrize("args,needle", [
    (["--candidates", "torsion"], "'torsion' is not a homogeneous test kind"),
    (["--range", "uniaxial=3:1.05"], "--range 'uniaxial=3:1.05'"),
    (["--range", "planar=a:b"], "expected KIND=LO:HI"),
    (["--noise", "-0.1"], "--noise -0.1: must be > 0"),
    (["--points", "2"], "--points 2: must be 3..10000"),
    (["--combine", "9"], "--combine 9: must be 1..4"),
    (["--expect", "C10=0.3"], "--expect: missing C01"),
    (["--expect", "C10=0.3,C02=1"], "--expect 'C02=1'"),
])
def test_cli_bad_input_exits_2_and_writes_nothing(tmp_path, args, needle):
    f = _fit_file(tmp_path)
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out"), *args])
    assert res.exit_code == 2
    assert needle in " ".join(res.output.split())
    assert not (tmp_path / "out").exists()


def test_cli_warns_when_the_data_leave_the_card_undetermined(tmp_path):
    f = _fit_file(tmp_path)
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out")])
    d = json.loads((tmp_path / "out" / "design.json").read_text())
    assert "--expect" in d["warnings"][0] and "give the expected constants" in " ".join(res.output.split())


def test_cli_noise_free_data_need_noise(tmp_path):
    f = _fit_file(tmp_path, kind="uniaxial", noise=0.0)
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out")])
    assert res.exit_code == 2 and "give --noise" in " ".join(res.output.split())
