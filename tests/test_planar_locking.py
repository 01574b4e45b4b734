"""Planar tension of a near-incompressible strip: a locked mesh's stop is not called a loss of
stability, and what the planar test measures matches the closed-form pure-shear state.

The case (reported): a clamped Mooney–Rivlin strip 4 × 40 × 1 mm (C10 = 0.30, C01 = 0.05 MPa,
K = 100 MPa: μ = 0.7 MPa, E = 2.0951 MPa, ν = 0.4965), mesh.size 1, displacement-only hexahedra
(one through the thickness). That mesh locks: its K_ff turns indefinite at stretch 1.216 with a mode
flapping the free ends, and it measured E = 4.98 MPa, ν = 0.5156. The material is Drucker-stable
and strongly elliptic along pure shear (checked here from the closed-form energy, not vlab's), and
the same mesh with the mixed formulation stays positive definite to stretch 1.3.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from vlab.checks.buckling import CriticalState
from vlab.checks.locking import locking_free
from vlab.materials import build_material
from vlab.materials.homogeneous import planar
from vlab.measure.planar import planar_constants
from vlab.measure.recorder import Curve
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import parse_scene

C10, C01, K = 0.30, 0.05, 100.0
MU = 2 * (C10 + C01)


def strip(formulation: str | None = None, stretch: float = 1.3) -> dict:
    mesh = {"size": 1.0, "cell": "hex"} | ({"formulation": formulation} if formulation else {})
    return {"name": "planar-mr", "specimen": {"shape": "planar-tension", "height": 4.0, "width": 40.0, "thickness": 1.0},
            "mesh": mesh, "material": {"model": "mooney-rivlin", "C10": C10, "C01": C01, "K": K},
            "test": {"kind": "planar", "grips": "clamped", "stretch": stretch, "steps": 10}}


def _psi(F: np.ndarray) -> float:
    """Compressible Mooney–Rivlin, written out here: C10(Ī₁ − 3) + C01(Ī₂ − 3) + K/2 (J − 1)² (MPa)."""
    J = np.linalg.det(F)
    C = F.T @ F
    I1 = np.trace(C)
    I2 = 0.5 * (I1**2 - np.trace(C @ C))
    return C10 * (J ** (-2 / 3) * I1 - 3) + C01 * (J ** (-4 / 3) * I2 - 3) + 0.5 * K * (J - 1) ** 2


def _hessian(f, x: np.ndarray, h: float = 1e-4) -> np.ndarray:
    """Central differences of central differences (error O(h²) ~ 1e-8 relative here)."""
    n = len(x)
    H = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            e_i, e_j = np.eye(n)[i] * h, np.eye(n)[j] * h
            H[i, j] = (f(x + e_i + e_j) - f(x + e_i - e_j) - f(x - e_i + e_j) + f(x - e_i - e_j)) / (4 * h * h)
    return 0.5 * (H + H.T)


def _log_psi(eps: np.ndarray) -> float:
    return _psi(np.diag(np.exp(eps)))


def _thickness(lam: float) -> float:
    """t of F = diag(λ, 1, t) with τ₃ = ∂ψ/∂ε₃ = 0 (pure shear, free thickness)."""
    h = 1e-6
    return brentq(lambda t: (_log_psi(np.log([lam, 1.0, t * np.exp(h)])) - _log_psi(np.log([lam, 1.0, t * np.exp(-h)])))
                  / (2 * h), 0.3, 1.5)


@pytest.mark.parametrize("lam", [1.1, 1.216, 1.5])
def test_the_card_is_drucker_stable_and_strongly_elliptic_along_pure_shear_at_the_reported_stop(lam):
    t = _thickness(lam)
    D = _hessian(_log_psi, np.log([lam, 1.0, t]))  # dτ_i/dε_j (Drucker: positive definite)
    assert np.linalg.eigvalsh(D).min() > 1.5 * MU  # 1.24 MPa at λ = 1.216 (2μ = 1.4 at rest)
    A = _hessian(lambda f: _psi(f.reshape(3, 3)), np.diag([lam, 1.0, t]).ravel()).reshape(3, 3, 3, 3)
    rng = np.random.default_rng(0)
    N = rng.standard_normal((300, 3))
    N /= np.linalg.norm(N, axis=1)[:, None]
    acoustic = min(np.linalg.eigvalsh(np.einsum("iJkL,J,L->ik", A, n, n)).min() for n in N)
    assert acoustic > 0.9 * MU  # 0.667 MPa at λ = 1.216
    assert t == pytest.approx(planar(build_material(parse_scene(strip()).material), lam).lateral_stretch, rel=1e-5)


@pytest.fixture(scope="module")
def locked():
    return run_scene(parse_scene(strip("displacement")))


def test_the_locked_strip_s_stop_is_called_unconfirmed_and_names_the_mixed_formulation(locked):
    reason = locked.history.failure.reason
    assert "unconfirmed loss of stability" in reason and "not evidence of a physical instability" in reason
    assert "mesh.formulation = 'mixed'" in reason
    critical = locked.solver.critical_state
    assert critical.suspect and critical.non_elliptic_fraction == 0.0 and not critical.sideways
    assert 1.2 < critical.stretch_unstable[0] < 1.23


def test_the_locked_strip_reports_no_poisson_ratio_above_one_half_nor_the_E_built_on_it(locked):
    m = result_to_dict(locked)["measured"]
    assert m["E"] is None and m["nu"] is None
    assert m["thickness_strain_ratio"] > 1.0 and "thickness strain ratio" in m["note"]
    assert m["planar_modulus"] > 2 * 4 * MU  # the locked strip: 6.78 MPa against E/(1 − ν²) = 2.78


def test_with_the_default_formulation_the_strip_reaches_its_stretch_by_the_mixed_re_check():
    result = run_scene(parse_scene(strip()))
    data = result_to_dict(result)
    assert data["converged"], data["failure"]
    assert result.scene.mesh.formulation == "mixed"
    assert "artefact of the locked elements" in data["warnings"][0]
    assert all(r["negative_eigenvalues"] == 0 and r["zero_eigenvalues"] == 0 for r in data["stability"])
    E = 9 * K * MU / (3 * K + MU)
    assert data["measured"]["E"] == pytest.approx(E, rel=0.02)  # 2.1146 against 2.0951 MPa
    assert data["measured"]["nu"] <= 0.5


def test_an_explicit_formulation_is_never_replaced():
    assert locking_free(parse_scene(strip("displacement"))) is None
    assert locking_free(parse_scene(strip("mixed"))) is None
    assert locking_free(parse_scene(strip())).mesh.formulation == "mixed"


def _critical(**kw) -> CriticalState:
    base = dict(stretch_stable=[1.2], stretch_unstable=[1.21], eigenvalue_stable=1e-3, eigenvalue_unstable=-1e-3,
                force_stable=[1.0], negative_eigenvalues=1, lateral_fraction=0.0, mode=np.zeros(3),
                non_elliptic_fraction=0.0, locking_nu=0.4965)
    return CriticalState(**(base | kw))


def test_only_a_local_mode_of_an_elliptic_material_on_locking_elements_is_suspect():
    assert _critical().suspect
    assert not _critical(locking_nu=None).suspect  # a locking-free mesh: a true stop
    assert not _critical(non_elliptic_fraction=0.1).suspect  # the material's own instability
    assert not _critical(lateral_fraction=0.9, stretch_unstable=[0.9]).suspect  # buckling
    assert not _critical(lateral_fraction=0.9).suspect  # whole sections sway: not a local element mode


def _curve(r: float, noise: float = 0.0) -> Curve:
    eps = np.linspace(0.0, 0.003, 13)
    rng = np.random.default_rng(1)
    return Curve(t=list(eps), strain={0: list(eps)}, force={0: list(2.8 * eps)}, area0={0: 1.0},
                 thickness_strain=list(-r * eps + noise * rng.standard_normal(eps.size)), kind="planar")


@pytest.mark.parametrize("nu", [0.3, 0.45, 0.5])
def test_planar_constants_invert_the_plane_strain_closed_form(nu):
    E_p, r = 2.8, nu / (1 - nu)  # ε_y = 0, σ_z = 0: σ_x = E/(1 − ν²) ε_x, ε_z = −ν/(1 − ν) ε_x
    c = planar_constants(_curve(r), (0.0005, 0.0025), "regression")
    assert c.nu == pytest.approx(nu, rel=1e-9) and c.E == pytest.approx((1 - nu**2) * E_p, rel=1e-9)


def test_a_thickness_ratio_past_one_is_refused_unless_within_its_noise():
    assert planar_constants(_curve(1.064), (0.0005, 0.0025), "regression").nu is None
    noisy = planar_constants(_curve(1.0005, noise=2e-6), (0.0005, 0.0025), "regression")
    assert noisy.nu is not None and noisy.nu == pytest.approx(0.5, abs=1e-3)
    assert planar_constants(_curve(-0.6), (0.0005, 0.0025), "regression").nu is None  # ν < −1


@pytest.mark.parametrize("material", [{"model": "neo-hookean", "mu": 0.7, "K": 7000.0},
                                      {"model": "mooney-rivlin", "C10": 0.30, "C01": 0.05, "K": 7000.0}],
                         ids=["neo-hookean", "mooney-rivlin"])
def test_the_roller_block_in_pure_shear_gives_the_closed_form_planar_modulus_and_curve(material):
    """F = diag(λ, 1, 1/λ) (K/μ = 1e4): P₁₁ = 2 (C10 + C01)(λ − λ⁻³), E_p → 4μ, ν → ½, E → 3μ."""
    scene = {"name": "ps", "specimen": {"shape": "block", "size": [4.0, 3.0, 2.0]}, "mesh": {"size": 2.0, "cell": "hex"},
             "material": material, "test": {"kind": "planar", "grips": "roller", "stretch": 1.5, "steps": 5}}
    data = result_to_dict(run_scene(parse_scene(scene)))
    m = data["measured"]
    # the slope over the window is dP₁₁/dλ = μ(1 + 3λ⁻⁴) at its centre: 4μ(1 − 3ε) to first order
    centre = 1.0 + float(np.mean(m["window"]))
    assert m["planar_modulus"] == pytest.approx(MU * (1 + 3 * centre**-4), rel=1e-3)  # 2.7867 (4μ = 2.8)
    assert m["nu"] == pytest.approx(0.5, abs=1e-3) and m["E"] == pytest.approx(3 * MU, rel=1e-2)
    lam = np.array(data["curve"]["stretch"])
    np.testing.assert_allclose(data["curve"]["stress"], MU * (lam - lam**-3), rtol=5e-4, atol=1e-6)  # 1.0e-4 measured (K/μ = 1e4)
