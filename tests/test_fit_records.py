"""Lab records in `vlab fit`: raw exports cleaned with known answers, Prony series from relaxation
and DMA records round-tripped, the history matching `vlab run`, and clear errors."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from vlab.fields import SceneError
from vlab.identify.datasets import Dataset
from vlab.identify.fitfile import FitSpec, parse_fit
from vlab.identify.fitting import fit_any
from vlab.identify.laws import law_for
from vlab.identify.records.prony import PronySpec, dynamic_moduli, history_stress
from vlab.identify.records.raw import clean
from vlab.identify.states import Constitutive

NH = Constitutive(law_for("neo-hookean"))
MR = Constitutive(law_for("mooney-rivlin"))
SPECIMENS = Path(__file__).resolve().parents[1] / "specimens" / "records"
OPTS = {"zero": "none", "trim": None, "resample": None, "smooth": "none", "toe_window": 2}


def _ramp_hold(stretch=1.5):
    t = np.r_[np.arange(1, 11) / 10, 1.0 + np.geomspace(0.1, 50.0, 20)]
    return t, 1.0 + np.minimum(t, 1.0) * (stretch - 1.0)


def _relax_set(model, x, prony, test="uniaxial"):
    t, lam = _ramp_hold()
    y = np.real(history_stress(model, prony, np.asarray(x, float)[None, :], test, t, lam)[0])
    return Dataset("relax", "relax.csv", "relaxation", "fit", 1.0, "nominal", t, lam, y, extra={"test": test})


def _dma_set(x, prony, modulus="tensile"):
    f = np.geomspace(0.01, 10.0, 31)
    s, l = dynamic_moduli(NH, prony, np.asarray(x, float)[None, :], f, modulus)
    return Dataset("dma", "dma.csv", "dma", "fit", 1.0, "nominal", f, None, np.r_[s[0], l[0]],
                   extra={"modulus": modulus})


def _fit(model, sets, prony, starts=3):
    return fit_any(FitSpec("t", model, tuple(sets), starts=starts, effects={"viscoelastic": prony}))


# --- raw clean-up, known answers -------------------------------------------------------------------------

def test_toe_and_offset_removed_exactly():
    L0, A0, mu = 25.0, 12.0, 0.6
    lam = np.linspace(1.0, 1.02, 5)  # a straight start (small strain): the tangent's intercept is exact
    lam = np.r_[lam, np.linspace(1.03, 2.0, 30)]
    u_true, F_true = (lam - 1) * L0, 3 * mu * (lam - 1) * A0
    F_true[5:] = mu * (lam[5:] - lam[5:] ** -2) * A0
    toe, offset = 0.7, 1.5
    u_toe = np.linspace(0.0, toe, 8)[:-1]
    u = np.r_[u_toe, u_true + toe]
    F = np.r_[0.01 * F_true[1] * (u_toe / toe) ** 3, F_true] + offset
    lam_c, P, rec = clean(u, F, L0, A0, OPTS | {"zero": "toe"}, "x.csv", {"force": "F"}, np.arange(2, 2 + len(u)))
    step = rec["steps"][0]
    assert step["force_offset_N"] == offset and abs(step["toe_extent_mm"] - toe) < 1e-12
    assert step["points_removed"] == 7 + 1  # the toe and the reading at the zero itself (put back as (0, 0))
    assert np.allclose(lam_c, lam, atol=1e-13) and np.allclose(P, F_true / A0, atol=1e-12)


def test_zero_first_removes_the_first_reading():
    u, F = np.linspace(0.3, 10.3, 11), np.linspace(2.0, 12.0, 11)
    lam, P, rec = clean(u, F, 10.0, 2.0, OPTS | {"zero": "first"}, "x.csv", {}, np.arange(11))
    assert lam[0] == 1.0 and P[0] == 0.0 and rec["steps"][0]["displacement_offset_mm"] == 0.3
    assert np.allclose(P, (F - 2.0) / 2.0)


def test_resampling_preserves_the_curve_to_interpolation_error():
    lam = np.geomspace(1.0, 3.0, 200)
    P = 0.5 * (lam - lam ** -2)
    u = (lam - 1) * 20.0
    lam_r, P_r, rec = clean(u, P * 4.0, 20.0, 4.0, OPTS | {"resample": 37}, "x.csv", {}, np.arange(200))
    assert np.allclose(np.diff(lam_r), np.diff(lam_r)[0]) and len(lam_r) == 37
    h = np.max(np.diff(lam))
    bound = h * h / 8 * np.max(np.abs(-3.0 * lam ** -4))  # |P''| = 3 lam^-4 / 2 · 2 (mu = 0.5)
    err = np.abs(P_r - 0.5 * (lam_r - lam_r ** -2))
    assert np.max(err) <= bound and np.max(err) > 0


def test_smoothing_keeps_a_cubic_and_reduces_noise():
    lam = np.linspace(1.0, 2.0, 101)
    P = 0.2 + 0.3 * (lam - 1) + 0.1 * (lam - 1) ** 3
    _, Ps, _ = clean((lam - 1) * 10, P, 10.0, 1.0, OPTS | {"smooth": 11}, "x.csv", {}, np.arange(101))
    assert np.allclose(Ps, P, atol=1e-12)  # Savitzky–Golay of order 3 reproduces a cubic
    rng = np.random.default_rng(0)
    noisy = P + 0.01 * rng.standard_normal(101)
    _, Pn, _ = clean((lam - 1) * 10, noisy, 10.0, 1.0, OPTS | {"smooth": 11}, "x.csv", {}, np.arange(101))
    assert np.std(Pn - P) < 0.6 * np.std(noisy - P)


def test_units_through_pint(tmp_path):
    (tmp_path / "r.csv").write_text("u,F\n0,0\n0.1,0.05\n0.2,0.09\n0.3,0.12\n")
    data = {"model": {"name": "neo-hookean"}, "data": [{
        "file": "r.csv", "kind": "uniaxial", "columns": {"displacement": "u", "force": "F"},
        "geometry": {"gauge_length": 1.0, "area": 0.05, "force_units": "lbf", "length_units": "in"}}]}
    d = parse_fit(data, tmp_path).datasets[0]
    assert np.allclose(d.a, 1 + np.array([0, 0.1, 0.2, 0.3]))
    assert np.allclose(d.y, np.array([0, 0.05, 0.09, 0.12]) * 4.4482216152605 / (0.05 * 25.4 ** 2))


# --- Prony series: the history, round trips, DMA -------------------------------------------------------

def test_history_holds_to_the_ground_law_and_starts_instantaneous():
    x = np.r_[0.5, 0.4, 0.2, 0.3, 3.0]
    t = np.r_[1e-6, 1e-6 + np.geomspace(1.0, 1e4, 30)]  # a step to 1.3, then held very long
    lam = np.full_like(t, 1.3)
    P = history_stress(NH, PronySpec(2), x[None], "uniaxial", t, lam)[0]
    closed = lambda mu: mu * (1.3 - 1.3 ** -2)
    assert abs(P[0] / closed(0.5 * 1.6) - 1) < 1e-5 and abs(P[-1] / closed(0.5) - 1) < 1e-12


def test_dma_closed_form_matches_a_small_sinusoid_through_the_history():
    x = np.r_[0.6, 0.5, 0.7]  # mu, beta, tau (s)
    f = 0.3
    w = 2 * np.pi * f
    t = np.linspace(0, 40 / f, 40 * 800 + 1)[1:]
    eps = 1e-5 * np.sin(w * t)
    P = history_stress(NH, PronySpec(1), x[None], "uniaxial", t, 1 + eps)[0]
    late = t > 20 / f  # transient gone
    A = np.c_[np.sin(w * t[late]), np.cos(w * t[late])]
    a, b = np.linalg.lstsq(A, P[late] / 1e-5, rcond=None)[0]
    E1, E2 = dynamic_moduli(NH, PronySpec(1), x[None], [f], "tensile")
    assert abs(a / E1[0, 0] - 1) < 2e-4 and abs(b / E2[0, 0] - 1) < 2e-4


@pytest.mark.parametrize("test", ["uniaxial", "equibiaxial", "planar"])
def test_relaxation_round_trips(test):
    x = np.r_[0.6, 0.5, 0.3, 1.0, 10.0]
    out = _fit(NH, [_relax_set(NH, x, PronySpec(2), test)], PronySpec(2))
    p = out.data["parameters"]
    got = np.r_[p["mu"], p["beta"], p["tau"]]
    assert out.converged and np.allclose(got, x, rtol=1e-6)


def test_relaxation_with_fixed_tau_and_mooney_rivlin_ground_round_trips():
    x = np.r_[0.4 + 0.1, 0.1, 0.6, 0.2]  # MR internal (s = C10 + C01, C01), beta with tau fixed
    prony = PronySpec(2, (1.0, 10.0))
    out = _fit(MR, [_relax_set(MR, x, prony)], prony)
    p = out.data["parameters"]
    assert np.allclose([p["C10"], p["C01"], *p["beta"]], [0.4, 0.1, 0.6, 0.2], rtol=1e-6)


def test_dma_round_trips_and_joins_a_relaxation_record():
    x = np.r_[0.6, 0.4, 0.3, 0.2, 0.05, 0.5, 5.0]
    prony = PronySpec(3)
    out = _fit(NH, [_dma_set(x, prony)], prony)
    p = out.data["parameters"]
    assert np.allclose(np.r_[p["mu"], p["beta"], p["tau"]], x, rtol=1e-6)
    both = _fit(NH, [_dma_set(x, prony), _relax_set(NH, x, prony)], prony)
    p = both.data["parameters"]
    assert np.allclose(np.r_[p["mu"], p["beta"], p["tau"]], x, rtol=1e-6)
    assert "[effects.viscoelastic]" in both.data["card"]["toml"]


def test_relaxation_without_viscoelastic_is_named_with_its_misfit():
    x = np.r_[0.6, 0.5, 0.3, 1.0, 10.0]
    out = _fit(NH, [_relax_set(NH, x, PronySpec(2))], None)
    w = " ".join(out.data["warnings"])
    assert "fitted without [model] viscoelastic" in w and "rms misfit" in w
    assert out.data["datasets"][0]["rms_relative"] > 0.05


def test_the_fitted_card_run_by_vlab_reproduces_the_history():
    """`vlab run` of a block with the fitted card, relaxation protocol: its stress against the
    history model at the run's own times (the only difference: the card's K = 1e5 mu0)."""
    from vlab.run import run_scene
    from vlab.scene import parse_scene

    x = np.r_[0.6, 0.5, 0.3, 1.0, 10.0]
    spec = FitSpec("t", Constitutive(law_for("neo-hookean"), K_over_mu=1e5), (_relax_set(NH, x, PronySpec(2)),),
                   starts=2, effects={"viscoelastic": PronySpec(2)})
    out = fit_any(spec)
    card = out.data["card"]
    scene = parse_scene({"name": "card", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
                         "mesh": {"size": 4.0, "order": 1, "cell": "hex"}, "material": card["material"],
                         "effects": card["effects"],
                         "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.5, "steps": 10,
                                  "protocol": "relaxation", "ramp_time": 1.0, "hold_time": 50.0, "hold_steps": 20}})
    result = run_scene(scene)
    assert result.converged
    c = result.curve
    t, lam, P = np.array(c.time), np.array(c.stretch[0]), c.column("stress")
    pred = np.real(history_stress(NH, PronySpec(2), out.x[None], "uniaxial", t, lam)[0])
    assert np.max(np.abs(P - pred)) / np.max(P) < 2e-5
    rec = spec.datasets[0]  # the run and the record share the end of the hold (t = 51 s)
    assert t[-1] == rec.a[-1] and abs(P[-1] / rec.y[-1] - 1) < 1e-4


# --- errors: file, row, column; exit 2, nothing written ------------------------------------------------

def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "vlab", "fit", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


RAW = """name = "raw"
[model]
name = "neo-hookean"
[[data]]
file = "r.csv"
kind = "uniaxial"
columns = { displacement = "u", force = "F", time = "t" }
"""


def test_raw_record_without_geometry_non_increasing_time_and_negative_loss_exit_2(tmp_path):
    (tmp_path / "r.csv").write_text("t,u,F\n0,0,0\n1,1,1\n1,2,2\n")
    (tmp_path / "a.toml").write_text(RAW)
    r = _cli(tmp_path / "a.toml", "--out", tmp_path / "o1", cwd=tmp_path)
    assert r.returncode == 2 and "geometry" in r.stderr and "r.csv" in r.stderr and not (tmp_path / "o1").exists()
    (tmp_path / "b.toml").write_text(RAW + "[data.geometry]\ngauge_length = 10.0\narea = 2.0\n")
    r = _cli(tmp_path / "b.toml", "--out", tmp_path / "o2", cwd=tmp_path)
    assert r.returncode == 2 and "r.csv row 4 column 't'" in r.stderr and not (tmp_path / "o2").exists()
    (tmp_path / "d.csv").write_text("f,E1,E2\n0.1,2,0.1\n1,2.2,-0.2\n")
    (tmp_path / "c.toml").write_text('[model]\nname = "neo-hookean"\nviscoelastic = { terms = 1 }\n[[data]]\n'
                                     'file = "d.csv"\nkind = "dma"\ncolumns = { frequency = "f", storage = "E1", '
                                     'loss = "E2" }\n')
    r = _cli(tmp_path / "c.toml", "--out", tmp_path / "o3", cwd=tmp_path)
    assert r.returncode == 2 and "d.csv row 3 column 'E2'" in r.stderr and not (tmp_path / "o3").exists()


def test_record_rules(tmp_path):
    (tmp_path / "d.csv").write_text("f,E1,E2\n0.1,2,0.1\n1,2.2,0.2\n")
    (tmp_path / "r.csv").write_text("t,lambda,P\n0,1.1,0\n")
    dma = {"file": "d.csv", "kind": "dma", "columns": {"frequency": "f", "storage": "E1", "loss": "E2"}}
    with pytest.raises(SceneError, match="no loss modulus"):
        parse_fit({"model": {"name": "neo-hookean"}, "data": [dma]}, tmp_path)
    with pytest.raises(SceneError, match="terms = N .* or tau"):
        parse_fit({"model": {"name": "neo-hookean", "viscoelastic": {}}, "data": [dma]}, tmp_path)
    with pytest.raises(SceneError, match="incompressible"):
        parse_fit({"model": {"name": "neo-hookean", "K": 100.0, "viscoelastic": {"terms": 1}}, "data": [dma]}, tmp_path)
    rel = {"file": "r.csv", "kind": "relaxation", "columns": {"time": "t", "stretch": "lambda", "stress": "P"}}
    with pytest.raises(SceneError, match="r.csv row 2 column 'lambda'.*at rest"):
        parse_fit({"model": {"name": "neo-hookean"}, "data": [rel]}, tmp_path)


@pytest.mark.parametrize("name", ["relaxation", "dma", "raw-uniaxial", "cycles"])
def test_shipped_examples_fit(tmp_path, name):
    r = _cli(SPECIMENS / f"{name}.fit.toml", "--out", tmp_path / "o", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    d = json.loads((tmp_path / "o" / "fit.json").read_text())
    figs = {"raw-uniaxial": "cleanup.png"}.get(name, "records.png")
    assert figs in d["files"] and (tmp_path / "o" / figs).is_file()
    truth = {"relaxation": {"mu": 0.6, "beta": [0.5, 0.3], "tau": [1.0, 10.0]},
             "dma": {"mu": 0.6, "beta": [0.4, 0.3, 0.2], "tau": [0.05, 0.5, 5.0]}, "raw-uniaxial": {"mu": 0.6},
             "cycles": {"mu": 0.6, "r": 2.0, "m": 0.3, "mullins_beta": 0.1}}[name]
    for k, v in truth.items():
        for i, vi in enumerate(np.atleast_1d(v)):
            key = f"{k}[{i}]" if isinstance(v, list) else k
            assert abs(np.atleast_1d(d["parameters"][k])[i] - vi) < 4 * d["uncertainty"][key]["standard_error"] + 1e-3 * vi


# --- cycles with Mullins softening ------------------------------------------------------------------------

def _cycle_path(amplitudes=(1.5, 2.0, 2.5), h=0.05):
    out = []
    for a in amplitudes:
        n = int(round((a - 1.0) / h))
        out += list(1.0 + h * np.arange(1, n + 1)) + list(a - h * np.arange(1, n + 1))
    return np.array(out)


def _cycles(model, x, mullins, branch="all", test="uniaxial"):
    from vlab.identify.records.cyclic import stress_along

    lam = _cycle_path()
    P = np.real(stress_along(model, {"mullins": mullins}, np.asarray(x, float)[None, :], test, lam)[0])
    step = np.diff(np.r_[1.0, lam])
    mask = {"all": np.ones(len(lam), bool), "loading": step >= 0, "unloading": step < 0}[branch]
    return Dataset("cycles", "c.csv", "cyclic", "fit", 1.0, "nominal", lam[mask], None, P[mask],
                   extra={"test": test, "stretch": lam, "time": None, "mask": mask, "branch": branch})


def _fit_mullins(model, sets, mullins, starts=3):
    return fit_any(FitSpec("t", model, tuple(sets), starts=starts, effects={"mullins": mullins}))


@pytest.mark.parametrize("branch,test", [("all", "uniaxial"), ("loading", "uniaxial"), ("all", "planar")])
def test_cycles_round_trip(branch, test):
    from vlab.identify.records.softening import MullinsSpec

    x = np.r_[0.6, 2.0, 0.3, 0.1]
    out = _fit_mullins(NH, [_cycles(NH, x, MullinsSpec(), branch, test)], MullinsSpec())
    p = out.data["parameters"]
    assert out.converged and np.allclose([p["mu"], p["r"], p["m"], p["mullins_beta"]], x, rtol=1e-6)
    assert out.data["card"]["effects"]["mullins"] == {"r": 2.0, "m": 0.3, "beta": 0.1}


def test_cycles_with_fixed_beta_over_mooney_rivlin_round_trip():
    from vlab.identify.records.softening import MullinsSpec

    x = np.r_[0.3 + 0.05, 0.05, 1.8, 0.2]  # MR internal (C10 + C01, C01), r, m; beta fixed at 0
    out = _fit_mullins(MR, [_cycles(MR, x, MullinsSpec(0.0))], MullinsSpec(0.0))
    p = out.data["parameters"]
    assert np.allclose([p["C10"], p["C01"], p["r"], p["m"]], [0.3, 0.05, 1.8, 0.2], rtol=1e-6)


@pytest.mark.parametrize("name,card", [("neo-hookean", [0.6]), ("mooney-rivlin", [0.3, 0.05]),
                                       ("yeoh", [0.3, -0.01, 0.002]), ("gent", [0.6, 20.0]),
                                       ("arruda-boyce", [0.6, 3.0]), ("ogden", [0.4, 0.01, 1.8, -2.0])])
def test_ground_energies_give_the_laws_stresses(name, card):
    """w_i = λ_i ∂ψ0/∂λ_i along uniaxial (incompressible): dψ0/dλ = P1, by the complex step."""
    from vlab.identify.records.softening import energy

    law = law_for(name, 2 if name == "ogden" else 1)
    model = Constitutive(law)
    lam = np.linspace(1.1, 2.5, 8)
    h = 1e-30
    lc = lam + 1j * h
    dpsi = np.imag(energy(law, card, lc, lc ** -0.5, lc ** -0.5)) / h
    from vlab.identify.states import response
    P = np.real(response(model, np.linalg.solve(law.transform, np.asarray(card, float))[None], "uniaxial", lam))[0]
    assert np.allclose(dpsi, P, rtol=1e-12)


def test_cycles_without_mullins_are_named_with_their_misfit():
    from vlab.identify.records.softening import MullinsSpec

    out = fit_any(FitSpec("t", NH, (_cycles(NH, np.r_[0.6, 2.0, 0.3, 0.1], MullinsSpec()),), starts=2,
                          effects={"viscoelastic": None, "mullins": None}))
    w = " ".join(out.data["warnings"])
    assert "fitted without [model] mullins" in w and "rms misfit" in w


def test_the_fitted_mullins_card_run_by_vlab_reproduces_the_cycles():
    """`vlab run` of a block with the fitted card, cyclic protocol: its stress against the
    softened history at the run's own stretches (the card's default K = 1000 mu0: ν = 0.4995 puts
    an O(μ/K) difference between the nearly incompressible block and the incompressible history)."""
    from vlab.identify.records.cyclic import stress_along
    from vlab.identify.records.softening import MullinsSpec
    from vlab.run import run_scene
    from vlab.scene import parse_scene

    x = np.r_[0.6, 2.0, 0.3, 0.1]
    out = _fit_mullins(NH, [_cycles(NH, x, MullinsSpec())], MullinsSpec(), starts=2)
    card = out.data["card"]
    scene = parse_scene({"name": "card", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
                         "mesh": {"size": 4.0, "order": 1, "cell": "hex"}, "material": card["material"],
                         "effects": card["effects"],
                         "test": {"kind": "uniaxial", "grips": "roller", "steps": 20,
                                  "protocol": "cyclic", "amplitudes": [1.5, 2.0, 2.5]}})
    result = run_scene(scene)
    assert result.converged
    lam, P = np.array(result.curve.stretch[0]), result.curve.column("stress")
    pred = np.real(stress_along(NH, {"mullins": MullinsSpec()}, out.x[None], "uniaxial", lam)[0])
    assert np.max(np.abs(P - pred)) / np.max(P) < 2e-4  # measured 6.3e-5
