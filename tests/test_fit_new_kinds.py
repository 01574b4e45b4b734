"""`vlab fit` data kinds torsion, inflation and confined-compression (vlab.identify.kinds): their
closed forms against formulas computed here, fits of noisy synthetic data back to the card within
its intervals, and bad data sets refused naming the field (exit 2, nothing written)."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fit_helpers import assert_inside, assert_jacobian_exact

from vlab.fields import SceneError
from vlab.identify.card import card_of
from vlab.identify.datasets import Dataset
from vlab.identify.fitfile import FitSpec, load_fit
from vlab.identify.fitting import fit_homogeneous
from vlab.identify.kinds.confined import axial_stress
from vlab.identify.kinds.inflation import pressure
from vlab.identify.kinds.torsion import torque_and_force
from vlab.identify.laws import law_for
from vlab.identify.solve import predict
from vlab.identify.states import Constitutive
from vlab.loading.thick_sphere import thick_sphere_pressure
from vlab.materials.card import build_material, parse_material

ROOT = Path(__file__).resolve().parents[1]
C10, C01, A = 0.3, 0.08, 5.0             # the Mooney–Rivlin card and cylinder radius (mm)
PSI = np.linspace(0.01, 0.2, 20)         # twist, rad/mm (surface shear up to 1)


def _x(model, card):
    return np.linalg.solve(model.transform, np.asarray(card, float))


def _material(model, values):
    """The FE library's law of the fitted card (vlab.materials), built from the card's table."""
    return build_material(parse_material(dict(card_of(model, values)["material"])))


def _rivlin(psi, a, c10, c01):
    """Rivlin's incompressible Mooney–Rivlin cylinder, length held: (M, N)."""
    return np.pi * psi * a**4 * (c10 + c01), -0.5 * np.pi * psi**2 * a**4 * (c10 + 2 * c01)


def test_mooney_rivlin_torsion_is_rivlins_closed_form():
    mr = Constitutive(law_for("mooney-rivlin"))
    psi = np.array([1e-3, 0.05, 0.2, 0.6])
    M, N = torque_and_force(mr, _x(mr, [C10, C01])[None], psi, A)
    M_ref, N_ref = _rivlin(psi, A, C10, C01)
    assert np.allclose(M[0], M_ref, rtol=1e-12) and np.allclose(N[0], N_ref, rtol=1e-11)


def test_an_ogden_card_that_is_mooney_rivlin_gives_rivlins_torque_and_force():
    # Ogden w_i = Σ 2μ_p/α_p λ_i^α_p with α = (2, −2), μ = (2 C10, 2 C01) is Mooney–Rivlin up to a pressure
    og = Constitutive(law_for("ogden", 2))
    psi = np.array([0.05, 0.2, 0.6])
    M, N = torque_and_force(og, np.array([[2 * C10, 2 * C01, 2.0, -2.0]]), psi, A)
    M_ref, N_ref = _rivlin(psi, A, C10, C01)
    assert np.allclose(M[0], M_ref, rtol=1e-12) and np.allclose(N[0], N_ref, rtol=1e-11)


@pytest.mark.parametrize("name,terms,card", [("yeoh", 1, [0.2, -0.01, 0.001]), ("gent", 1, [0.4, 30.0]),
                                             ("arruda-boyce", 1, [0.4, 5.0]), ("ogden", 2, [0.4, 0.02, 1.5, 5.0])])
def test_every_law_has_the_linear_torsional_stiffness_of_its_initial_modulus(name, terms, card):
    # M → (π/2) μ0 ψ a⁴ as ψ → 0; the axial force is second order, N/ψ² bounded and negative
    model = Constitutive(law_for(name, terms))
    M, N = torque_and_force(model, _x(model, card)[None], np.array([1e-5]), A)
    mu0 = model.law.mu0(card)
    assert M[0, 0] == pytest.approx(0.5 * np.pi * mu0 * 1e-5 * A**4, rel=1e-8)
    assert N[0, 0] < 0


def test_inflation_is_the_neo_hookean_thick_sphere_and_the_loading_modules_quadrature():
    mu, ratio = 0.4, (10.0 / 11.0) ** 3
    lam = np.array([1.0, 1.001, 1.2, 1.4264, 2.0, 3.0])
    p = pressure(Constitutive(law_for("neo-hookean")), np.array([[mu]]), lam, ratio)[0]
    lb = (1 + (lam**3 - 1) * ratio) ** (1 / 3)
    closed = 2 * mu * ((1 / lb + 1 / (4 * lb**4)) - (1 / lam + 1 / (4 * lam**4)))
    assert np.allclose(p, closed, rtol=1e-11, atol=1e-15)
    og = Constitutive(law_for("ogden", 2))
    card = [0.4, 0.02, 1.5, 5.0]
    material = _material(og, card)
    p = pressure(og, np.array([card]), lam[1:], ratio)[0]
    quad = [thick_sphere_pressure(material, float(v), ratio) for v in lam[1:]]
    assert np.allclose(p, quad, rtol=1e-9)  # Ŵ' = 2 (P11 − λ⁻³ P33) drops the library law's pressure


@pytest.mark.parametrize("name,terms,card", [("neo-hookean", 1, [0.5]), ("mooney-rivlin", 1, [0.25, 0.05]),
                                             ("yeoh", 1, [0.2, -0.01, 0.001]), ("ogden", 2, [0.4, 0.02, 1.5, 5.0])])
def test_confined_compression_is_the_librarys_stress_at_diag_lambda_1_1(name, terms, card):
    model = Constitutive(law_for(name, terms), "fixed", 20.0)
    lam = np.array([0.7, 0.85, 0.99, 1.1])
    P = axial_stress(model, _x(model, card)[None], lam)[0]
    material = _material(model, np.r_[card, 20.0])
    ref = [np.asarray(material.stress(np.diag([v, 1.0, 1.0])), float)[0, 0] for v in lam]
    assert np.allclose(P, ref, rtol=1e-9)


def _data(kind, a, y, extra):
    return Dataset(kind, f"{kind}.csv", kind, "fit", 1.0, "nominal", a, None, y, extra)


def _torsion_set(model, card, rng):
    d = _data("torsion", PSI, np.zeros(40), {"geometry": {"radius": A}, "outputs": ("torque", "axial_force")})
    y = np.real(predict(model, _x(model, card)[None], d))[0]
    return _data("torsion", PSI, y * (1 + 0.005 * rng.standard_normal(40)), d.extra)


@pytest.mark.parametrize("kind", ["torsion", "inflation", "confined-compression"])
def test_jacobians_of_the_new_kinds_are_exact(kind):
    model = Constitutive(law_for("ogden", 2), "fixed", 30.0)
    x = np.array([0.4, 0.02, 1.5, 5.0])
    extra = {"torsion": {"geometry": {"radius": A}, "outputs": ("torque", "axial_force")},
             "inflation": {"geometry": {"inner_radius": 10.0, "thickness": 2.0}, "outputs": ("pressure",)},
             "confined-compression": {"geometry": {}, "outputs": ("stress",)}}[kind]
    a = {"torsion": PSI[::4], "inflation": np.linspace(1.05, 2.5, 5)}.get(kind, np.linspace(0.7, 0.98, 5))
    d = _data(kind, a, np.zeros(len(a) * len(extra["outputs"])), extra)
    assert_jacobian_exact(model, x, d)


def test_noisy_mooney_rivlin_torsion_is_fitted_back_within_its_intervals():
    mr = Constitutive(law_for("mooney-rivlin"))
    out = fit_homogeneous(FitSpec("t", mr, (_torsion_set(mr, [C10, C01], np.random.default_rng(1)),), starts=4))
    assert out.converged and out.data["identifiability"]["identifiable"]  # the axial force separates C10, C01
    assert_inside(out, {"C10": C10, "C01": C01})
    assert out.data["trust"]["trustworthy"]


def test_torque_alone_fixes_only_c10_plus_c01():
    mr = Constitutive(law_for("mooney-rivlin"))
    d = _torsion_set(mr, [C10, C01], np.random.default_rng(1))
    torque = _data("torsion", PSI, d.y[:20], {"geometry": {"radius": A}, "outputs": ("torque",)})
    out = fit_homogeneous(FitSpec("t", mr, (torque,), starts=2))
    assert sum(mr.card_vector(out.x)) == pytest.approx(C10 + C01, rel=0.01)
    assert not out.data["identifiability"]["identifiable"]
    assert "only C10 + C01" in out.data["identifiability"]["warning"]


def test_a_noisy_neo_hookean_sphere_is_fitted_back_within_its_interval():
    nh = Constitutive(law_for("neo-hookean"))
    lam = np.linspace(1.05, 2.5, 25)
    extra = {"geometry": {"inner_radius": 10.0, "thickness": 1.0}, "outputs": ("pressure",)}
    p = pressure(nh, np.array([[0.4]]), lam, (10.0 / 11.0) ** 3)[0]
    noisy = p * (1 + 0.005 * np.random.default_rng(2).standard_normal(len(p)))
    out = fit_homogeneous(FitSpec("s", nh, (_data("inflation", lam, noisy, extra),), starts=2))
    assert out.converged
    assert_inside(out, {"mu": 0.4})


def test_confined_compression_with_uniaxial_data_is_fitted_back_to_mu_and_K():
    nh = Constitutive(law_for("neo-hookean"), "fit")
    x, rng = np.array([0.5, 20.0]), np.random.default_rng(3)
    die = np.linspace(0.99, 0.7, 16)
    y = axial_stress(nh, x[None], die)[0] * (1 + 0.005 * rng.standard_normal(16))
    uni = _data("uniaxial", np.linspace(1.05, 2.5, 16), np.zeros(16), None)
    yu = np.real(predict(nh, x[None], uni))[0] * (1 + 0.005 * rng.standard_normal(16))
    sets = (_data("confined-compression", die, y, {"geometry": {}, "outputs": ("stress",)}),
            _data("uniaxial", uni.a, yu, None))
    out = fit_homogeneous(FitSpec("c", nh, sets, starts=3))
    assert out.converged
    assert_inside(out, {"mu": 0.5, "K": 20.0})


def test_the_shipped_torsion_example_fits_its_card():
    spec = load_fit(ROOT / "specimens" / "torsion-fit" / "torsion-fit.toml")
    assert spec.datasets[0].extra["geometry"] == {"radius": 5.0}
    out = fit_homogeneous(spec)
    assert_inside(out, {"C10": C10, "C01": C01})


TORSION_CSV = "psi,M,N\n0.01,7.46,-0.045\n0.05,37.3,-1.13\n0.1,74.6,-4.52\n0.2,149.2,-18.1\n"
TORSION = '''[model]
name = "mooney-rivlin"
[[data]]
file = "t.csv"
kind = "torsion"
columns = {{ twist = "psi", torque = "M", axial_force = "N" }}
{extra}
'''


@pytest.mark.parametrize("extra,model,needle", [
    ("", "", "data[0].geometry is required for kind = 'torsion': [data.geometry] with radius"),
    ("[data.geometry]\nthickness = 1.0", "", "unknown key 'thickness' in [data[0].geometry] (allowed: radius)"),
    ("[data.geometry]", "", "data[0].geometry.radius is required for kind = 'torsion'"),
    ("[data.geometry]\nradius = 0", "", "data[0].geometry.radius must be > 0"),
    ('stress_measure = "true"\n[data.geometry]\nradius = 5.0', "", "data[0].stress_measure does not apply"),
    ('units = "MPa"\n[data.geometry]\nradius = 5.0', "", "data[0].units"),
])
def test_a_bad_torsion_data_set_names_the_field(tmp_path, extra, model, needle):
    (tmp_path / "t.csv").write_text(TORSION_CSV)
    f = tmp_path / "fit.toml"
    f.write_text(TORSION.format(extra=extra))
    with pytest.raises(SceneError) as err:
        load_fit(f)
    assert needle in str(err.value), str(err.value)


def _cli(tmp_path, toml, csv, name):
    (tmp_path / name).write_text(csv)
    (tmp_path / "fit.toml").write_text(toml)
    return subprocess.run([sys.executable, "-m", "vlab", "fit", "fit.toml", "-o", "out"], capture_output=True,
                          text=True, cwd=tmp_path, timeout=300)


def test_the_cli_refuses_an_inflation_set_without_its_thickness_with_exit_2(tmp_path):
    toml = ('[model]\nname = "neo-hookean"\n[[data]]\nfile = "s.csv"\nkind = "inflation"\n'
            'columns = { stretch = "lam", pressure = "p" }\ngeometry = { inner_radius = 10.0 }\n')
    r = _cli(tmp_path, toml, "lam,p\n1.1,0.01\n1.3,0.03\n", "s.csv")
    assert r.returncode == 2 and "data[0].geometry.thickness is required for kind = 'inflation'" in r.stderr + r.stdout
    assert "Traceback" not in r.stderr and not (tmp_path / "out").exists()


def test_the_cli_refuses_confined_compression_with_an_incompressible_model_with_exit_2(tmp_path):
    toml = ('[model]\nname = "neo-hookean"\n[[data]]\nfile = "d.csv"\nkind = "confined-compression"\n'
            'columns = { stretch = "lam", stress = "P" }\n')
    r = _cli(tmp_path, toml, "lam,P\n0.95,-1.0\n0.9,-2.1\n", "d.csv")
    assert r.returncode == 2 and "kind = \"confined-compression\" needs a compressible model" in r.stderr + r.stdout
    assert not (tmp_path / "out").exists()


def test_a_torque_of_the_wrong_sign_names_its_row(tmp_path):
    (tmp_path / "t.csv").write_text("psi,M\n0.01,7.46\n0.05,-37.3\n0.1,74.6\n")
    f = tmp_path / "fit.toml"
    f.write_text(TORSION.format(extra="[data.geometry]\nradius = 5.0").replace(', axial_force = "N"', ""))
    with pytest.raises(SceneError, match=r"t.csv row 3 column 'M': torque -37.3 at twist 0.05 has the sign opposite"):
        load_fit(f)
