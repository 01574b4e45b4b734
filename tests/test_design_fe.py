"""`vlab design` on FE-in-the-loop fit files: the Fisher information of a specimen's readings
(vlab.identify.fe_design) against the homogeneous closed form and Mooney–Rivlin's pure-shear
degeneracy."""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.identify.design import PlannedTest, assess, plan_rows
from vlab.identify.fe_design import SpecimenTest, specimen_rows
from vlab.identify.fe_loop import closed_form
from vlab.identify.fe_sensitivity import simulate
from vlab.identify.states import response


def _block(kind: str, material: str, grips: str = "roller", stretch: float = 1.5, steps: int = 10) -> str:
    return (f'name = "{kind}-block"\n[specimen]\nshape = "block"\nsize = [10.0, 4.0, 4.0]\n[mesh]\nsize = 4.0\n'
            f'order = 1\ncell = "hex"\n[material]\n{material}\n[test]\nkind = "{kind}"\ngrips = "{grips}"\n'
            f"stretch = {stretch}\nsteps = {steps}\n")


NH = 'model = "neo-hookean"\nmu = 0.4\nK = 2.0'
MR = 'model = "mooney-rivlin"\nC10 = 0.3\nC01 = 0.05\nK = 400.0'


def _fe(path: Path, text: str, params, model: str) -> dict:
    path.write_text(text)
    return {"scene_path": str(path), "scene_raw": tomllib.loads(text), "parameters": tuple(params), "model": model,
            "volumetric": None}


@pytest.mark.parametrize("params", [("mu",), ("mu", "K")])
def test_a_roller_block_predicts_the_homogeneous_uniaxial_standard_errors(tmp_path, params):
    """The roller block's state is homogeneous uniaxial, F = P A0 and e = λ − 1, so its readings'
    Fisher information is the closed form's at the same stretches and relative noise: equal to the
    solver's tolerance where the readings sit on recorded levels (λ = 1.05, 1.10, …, 1.5 with
    steps = 10 above the modulus window), to the cubic spline's error (1e-4) between them."""
    values = {"mu": 0.4, "K": 2.0}
    fe = _fe(tmp_path / "block.toml", _block("uniaxial", NH), params, "neo-hookean")
    sim = simulate(fe, values)
    model = closed_form(fe | {"fixed": values}, "fit" if "K" in params else "fixed")
    x = np.linalg.solve(model.transform, [values[n] for n in model.names])
    card = [values[n] for n in params]
    for points, tol in ((10, 1e-8), (12, 1e-4), (37, 1e-4)):
        hom = assess(plan_rows(model, x, PlannedTest("uniaxial", 1.05, 1.5, points), True), 0.01, card, params)
        test = SpecimenTest(fe["scene_path"], "block", "uniaxial", "block", 5.0, 0.05, 0.5, points)
        got = assess(specimen_rows(sim, test, True), 0.01, card, params)
        for n in params:
            assert got["standard_errors"][n] == pytest.approx(hom["standard_errors"][n], rel=tol), (n, points)
        assert got["D"] == pytest.approx(hom["D"], rel=tol)


def test_a_biaxial_roller_block_is_read_on_both_axes_as_two_equibiaxial_tests(tmp_path):
    """Equal stretches on a roller block: both load cells read the equibiaxial closed form's force,
    each with its own 1 % noise, so F = 2 F_equibiaxial and every SE is the equibiaxial one / √2
    (to the solver's tolerance on recorded levels, to 1e-4 between them)."""
    values = {"mu": 0.4, "K": 2.0}
    text = _block("biaxial", NH).replace("size = [10.0, 4.0, 4.0]", "size = [10.0, 10.0, 4.0]").replace(
        "stretch = 1.5", "stretch = [1.5, 1.5]")
    fe = _fe(tmp_path / "biaxial.toml", text, ("mu", "K"), "neo-hookean") | {"axes": (0, 1)}
    sim = simulate(fe, values)
    model = closed_form(fe | {"fixed": values}, "fit")
    x = np.linalg.solve(model.transform, [values[n] for n in model.names])
    for points, tol in ((10, 1e-8), (12, 1e-4)):
        hom = assess(plan_rows(model, x, PlannedTest("equibiaxial", 1.05, 1.5, points), True), 0.01, [0.4, 2.0],
                     ["mu", "K"])
        test = SpecimenTest(fe["scene_path"], "biaxial", "biaxial", "block", 5.0, 0.05, 0.5, points)
        rows = specimen_rows(sim, test, True)
        assert rows.shape == (2 * points, 2)
        got = assess(rows, 0.01, [0.4, 2.0], ["mu", "K"])
        for n in ("mu", "K"):
            assert got["standard_errors"][n] * np.sqrt(2) == pytest.approx(hom["standard_errors"][n], rel=tol)


@pytest.mark.parametrize("gauge,elongation_sd", [(5.0, 0.001), (2.0, 0.001), (5.0, 0.01)])
def test_extensometer_scatter_enters_as_the_effective_variance_of_the_closed_form(tmp_path, gauge, elongation_sd):
    """Errors in both variables, to first order: a strain scatter σ_e = σ_u/G adds (∂P/∂λ σ_e)² to
    each reading's variance, so I(μ) = Σ (∂P/∂μ / P)² / (s² + (∂P/∂λ σ_e / P)²) with P(λ; μ) the
    closed form's uniaxial stress (derivatives by central differences here, 1e-6 steps). The
    roller block's spline reproduces it to 1e-5 (its derivative between recorded levels)."""
    values, s = {"mu": 0.4, "K": 2.0}, 0.01
    fe = _fe(tmp_path / "block.toml", _block("uniaxial", NH), ("mu",), "neo-hookean")
    sim = simulate(fe, values)
    model = closed_form(fe | {"fixed": values}, "fixed")

    def P(mu, lam):
        return np.real(response(model, np.array([[mu]]), "uniaxial", lam))[0]

    for points in (10, 37):
        lam, h = np.linspace(1.05, 1.5, points), 1e-6
        dmu, dlam = (P(0.4 + h, lam) - P(0.4 - h, lam)) / (2 * h), (P(0.4, lam + h) - P(0.4, lam - h)) / (2 * h)
        p, se_e = P(0.4, lam), elongation_sd / gauge
        expected = 1.0 / np.sqrt(np.sum((dmu / p) ** 2 / (s * s + (dlam * se_e / p) ** 2)))
        test = SpecimenTest(fe["scene_path"], "block", "uniaxial", "block", gauge, 0.05, 0.5, points)
        got = assess(specimen_rows(sim, test, True, s, elongation_sd), s, [0.4], ["mu"])["standard_errors"]["mu"]
        assert got == pytest.approx(expected, rel=1e-5)
        no_strain_noise = assess(specimen_rows(sim, test, True), s, [0.4], ["mu"])["standard_errors"]["mu"]
        assert got > no_strain_noise * (1 + 1e-3)  # the effect is there (1 % to 26 % here)


def _readings(tmp_path: Path, fe: dict, values: dict) -> None:
    sim = simulate(fe, values)
    (tmp_path / "r.csv").write_text("strain,force\n" + "".join(f"{float(e)!r},{float(f)!r}\n"
                                                               for e, f in zip(sim.strain[:, 0], sim.force[:, 0])))


def _fit_file(tmp_path: Path, model: str, params, residual: str = "relative") -> Path:
    f = tmp_path / "fit.toml"
    f.write_text(f'name = "spec"\n[model]\nname = "{model}"\n[[data]]\nfile = "r.csv"\nkind = "specimen"\n'
                 f'[fe]\nscene = "scene.toml"\nparameters = {json.dumps(list(params))}\ncache = false\n'
                 f'[options]\nresidual = "{residual}"\n')
    return f


def _by_tests(entries):
    return {tuple(Path(t.get("scene", t["kind"])).stem for t in e["tests"]): e for e in entries}


def test_mooney_rivlin_pure_shear_specimen_alone_does_not_separate_c10_and_c01_and_a_uniaxial_one_does(tmp_path):
    """Pure shear has Ī1 = Ī2 at J = 1, so only C10 + C01 is seen; the roller block's finite K
    (K/μ0 ≈ 570) breaks the tie only by O(1 − J): correlation 1 to 1e-5, relative errors above
    100 % (C01's above 1000 %) at 1 % noise. A uniaxial specimen added resolves both to < 10 %."""
    fe = _fe(tmp_path / "scene.toml", _block("uniaxial", MR, stretch=2.0, steps=10), ("C10", "C01"), "mooney-rivlin")
    (tmp_path / "planar.toml").write_text(_block("planar", MR, stretch=2.0, steps=10))
    _readings(tmp_path, fe, {"C10": 0.3, "C01": 0.05, "K": 400.0})
    f = _fit_file(tmp_path, "mooney-rivlin", ("C10", "C01"))
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out"), "--specimens",
                                   str(tmp_path / "planar.toml"), "--expect", "C10=0.3,C01=0.05", "--noise", "0.01",
                                   "--range", "specimen=0.05:0.95", "--combine", "2"])
    assert res.exit_code == 0, res.output
    d = json.loads((tmp_path / "out" / "design.json").read_text())
    out = _by_tests(d["candidates"])
    planar, both = out[("planar",)], out[("scene", "planar")]
    assert planar["verdict"] != "well-posed" and planar["worst_correlation"] > 0.99999
    assert min(planar["relative_errors"].values()) > 1.0 and max(planar["relative_errors"].values()) > 10.0
    assert both["verdict"] == "well-posed" and max(both["relative_errors"].values()) < 0.1
    assert out[("scene",)]["verdict"] == "well-posed"
    assert d["candidates"][-1] is planar  # the ill-conditioned one ranks last
    assert [r["test"] for r in d["fe"]["runs"]] == ["uniaxial", "planar"] and d["fit_converged"] is None
    assert d["candidates"][0]["tests"][0]["range"] == [0.05, 0.95]


def test_cli_fits_the_readings_and_plans_gauge_lengths_around_the_fitted_card(tmp_path):
    """Without --expect and --noise the file is fitted first; the design is around the fitted μ at
    the fit's residual scatter, and a roller block's readings do not depend on the gauge length."""
    fe = _fe(tmp_path / "scene.toml", _block("uniaxial", NH), ("mu",), "neo-hookean")
    sim = simulate(fe, {"mu": 0.4, "K": 2.0})
    noisy = sim.force[:, 0] * (1 + 0.01 * np.random.default_rng(1).standard_normal(len(sim.force)))
    (tmp_path / "r.csv").write_text("strain,force\n" + "".join(f"{float(e)!r},{float(v)!r}\n"
                                                               for e, v in zip(sim.strain[:, 0], noisy)))
    f = _fit_file(tmp_path, "neo-hookean", ("mu",))
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out"), "--gauge-lengths", "2,4",
                                   "--points", "10", "--range", "specimen=0.05:0.5", "--candidates", "uniaxial"])
    assert res.exit_code == 0, res.output
    d = json.loads((tmp_path / "out" / "design.json").read_text())
    assert d["parameters_from"] == "fit" and d["fit_converged"] is True
    assert abs(d["parameters"]["mu"] - 0.4) < 0.01 and d["noise"]["source"] == "fit"
    assert [r["gauge_length_mm"] for r in d["fe"]["runs"]] == [5.0, 2.0, 4.0]
    singles = [e for e in d["candidates"] if len(e["tests"]) == 1]
    se = [e["standard_errors"]["mu"] for e in singles]
    assert len(singles) == 4 and max(se) == pytest.approx(min(se), rel=1e-4)  # 3 gauges + the closed form
    assert d["present_data"]["verdict"] == "well-posed" and d["answer"].startswith("add ")
    assert (tmp_path / "out" / "index.html").is_file()
    # an extensometer that scatters by 5 µm: the longest gauge length reads the strain best
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out2"), "--gauge-lengths", "2,8",
                                   "--points", "10", "--range", "specimen=0.05:0.5", "--extensometer-std", "0.005",
                                   "--expect", "mu=0.4", "--noise", "0.01", "--combine", "1"])
    assert res.exit_code == 0, res.output
    d = json.loads((tmp_path / "out2" / "design.json").read_text())
    assert [e["tests"][0]["gauge_length_mm"] for e in d["candidates"]] == [8.0, 5.0, 2.0]
    assert d["candidates"][-1]["standard_errors"]["mu"] > 1.01 * d["candidates"][0]["standard_errors"]["mu"]


@pytest.mark.parametrize("args,needle", [
    (["--specimens", "nowhere.toml"], "'nowhere.toml' is not a scene file"),
    (["--gauge-lengths", "-3"], "--gauge-lengths '-3': expected comma-separated gauge lengths in mm"),
    (["--gauge-lengths", "20"], "--gauge-lengths 20 on fe.scene: scene.toml: measure.gauge_length must be > 0 and < 10"),
    (["--range", "specimen=0.5:0.1"], "--range 'specimen=0.5:0.1'"),
    (["--range", "specimen=0.05:3"], "not covered by the scene's test"),
    (["--combine", "3"], "--combine 3: must be 1..2"),
    (["--specimens", "{tmp}/other.toml"], "--specimens other.toml: the scene's material.model is 'mooney-rivlin'"),
    (["--expect", "K=2"], "--expect 'K=2'"),
    (["--extensometer-std", "-0.001"], "--extensometer-std -0.001: must be >= 0"),
])
def test_cli_bad_specimen_design_input_exits_2_and_writes_nothing(tmp_path, args, needle):
    fe = _fe(tmp_path / "scene.toml", _block("uniaxial", NH), ("mu",), "neo-hookean")
    _readings(tmp_path, fe, {"mu": 0.4, "K": 2.0})
    (tmp_path / "other.toml").write_text(_block("uniaxial", MR))
    (tmp_path / "planar.toml").write_text(_block("planar", NH))
    f = _fit_file(tmp_path, "neo-hookean", ("mu",))
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out"), "--noise", "0.01",
                                   "--expect", "mu=0.4", "--specimens", str(tmp_path / "planar.toml"),
                                   *(a.format(tmp=tmp_path) for a in args)],
                             catch_exceptions=False)
    assert res.exit_code == 2, res.output
    assert needle in " ".join(res.output.split())
    assert not (tmp_path / "out").exists()


def test_cli_homogeneous_candidates_need_relative_residuals_and_fe_options_need_specimen_data(tmp_path):
    fe = _fe(tmp_path / "scene.toml", _block("uniaxial", NH), ("mu",), "neo-hookean")
    _readings(tmp_path, fe, {"mu": 0.4, "K": 2.0})
    f = _fit_file(tmp_path, "neo-hookean", ("mu",), residual="absolute")
    res = CliRunner().invoke(app, ["design", str(f), "--out", str(tmp_path / "out"), "--noise", "0.01",
                                   "--expect", "mu=0.4", "--candidates", "uniaxial"])
    assert res.exit_code == 2 and "needs options.residual = \"relative\"" in " ".join(res.output.split())
    (tmp_path / "d.csv").write_text("stretch,stress\n1.1,0.1\n1.2,0.2\n1.3,0.3\n")
    (tmp_path / "h.toml").write_text('[model]\nname = "neo-hookean"\n[[data]]\nfile = "d.csv"\nkind = "uniaxial"\n')
    res = CliRunner().invoke(app, ["design", str(tmp_path / "h.toml"), "--out", str(tmp_path / "out"),
                                   "--gauge-lengths", "2"])
    assert res.exit_code == 2 and "need a fit file with a data set of kind = \"specimen\"" in " ".join(res.output.split())
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_predicted_standard_errors_match_the_scatter_of_fe_in_the_loop_fits():
    """12 noisy curves of a clamped Mooney–Rivlin block (benchmarks/design_fe_scatter.py), each
    fitted through vlab's own test: the fitted constants' standard deviation over the seeds against
    the design's prediction. A 12-seed standard deviation has a sampling error of about 21 %, so
    the band 0.5..1.6 is ±2.5 of those; benchmarks/DESIGN.md records 30 seeds (ratios 1.01–1.08)."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from benchmarks.design_fe_scatter import run

    r = run("block", 12, 0.01)
    assert r["converged"] == 12 and r["verdict"] == "well-posed"
    for name, predicted, scatter, mean in r["rows"]:
        assert 0.5 < scatter / predicted < 1.6, name
