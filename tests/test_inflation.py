"""Inflation of a spherical shell under volume control (vlab.loading.kinds.inflation) on the
cubed-sphere octant (vlab.geometry.sphere_shell), against closed forms computed here:

- thick Neo-Hookean sphere (incompressible): p = 2μ [(1/λ_b + 1/(4λ_b⁴)) − (1/λ_a + 1/(4λ_a⁴))],
  b³ − a³ = B³ − A³; the FE (K/μ = 1000, mixed hexahedra, one layer) passes the maximum and goes on
  to λ_a = 2.5. Measured at A = 10, H = 1, h = 1 mm: largest |p − p_closed| / max p = 1.6e-3
  (`vlab run specimens/sphere-inflation.toml`); held to 5e-3;
- its limit point: the maximum of the closed form (found here numerically), and the thin-shell
  limit λ = 7^(1/6) as H/A → 0;
- a Mooney–Rivlin balloon with C01/C10 = 0.3, above the thin-shell threshold 0.2143 where the
  maximum disappears, shows none.
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from vlab.geometry.sphere_shell import cavity_volume, count_shell, shell_mesh
from vlab.geometry.mesh_check import check_mesh
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene

MU = 0.4


def scene(inner: float, thickness: float, stretch: float, steps: int, size: float = 1.0,
          material: dict | None = None, test: dict | None = None) -> dict:
    return {"name": "balloon", "specimen": {"shape": "sphere-shell", "inner_radius": inner, "thickness": thickness},
            "mesh": {"size": size, "cell": "hex", "formulation": "mixed"},
            "material": material or {"model": "neo-hookean", "mu": MU, "K": 1000 * MU},
            "test": {"kind": "inflation", "stretch": stretch, "steps": steps} | (test or {})}


@cache
def run(inner: float, thickness: float, stretch: float, steps: int, model: str = "neo-hookean") -> dict:
    material = None if model == "neo-hookean" else {"model": "mooney-rivlin", "C10": 0.2, "C01": 0.06, "K": 260.0}
    return result_to_dict(run_scene(parse_scene(scene(inner, thickness, stretch, steps, material=material))))


def neo_hookean_thick(lam_a: float, inner: float, thickness: float) -> float:
    A, B = inner, inner + thickness
    lam_b = (1.0 + (lam_a**3 - 1.0) * (A / B) ** 3) ** (1.0 / 3.0)
    return 2 * MU * ((1 / lam_b + 1 / (4 * lam_b**4)) - (1 / lam_a + 1 / (4 * lam_a**4)))


def closed_form_maximum(inner: float, thickness: float) -> float:
    found = minimize_scalar(lambda lam: -neo_hookean_thick(lam, inner, thickness), bounds=(1.05, 3.0),
                            method="bounded", options={"xatol": 1e-10})
    return float(found.x)


def test_a_thick_neo_hookean_balloon_passes_its_pressure_maximum_on_the_closed_form():
    data = run(10.0, 1.0, 2.5, 30)
    assert data["converged"], data["failure"]
    curve = data["curve"]
    closed = np.array([neo_hookean_thick(lam, 10.0, 1.0) for lam in curve["stretch"]])
    p = np.array(curve["pressure"])
    assert curve["stretch"][-1] == pytest.approx(2.5) and p[-1] < 0.75 * p.max()  # well past the maximum
    assert np.max(np.abs(p - closed)) / closed.max() < 5e-3
    np.testing.assert_allclose(curve["volume_ratio"], np.array(curve["stretch"]) ** 3, rtol=1e-14)
    # the kind's own reference (quadrature of the model's Ŵ') is the same closed form
    np.testing.assert_allclose(data["reference"]["pressure"], closed, rtol=1e-9, atol=1e-12)
    limit = data["measured"]["limit_point"]
    assert limit["stretch"] == pytest.approx(closed_form_maximum(10.0, 1.0), abs=0.01)
    assert limit["pressure"] == pytest.approx(neo_hookean_thick(closed_form_maximum(10.0, 1.0), 10.0, 1.0),
                                              rel=5e-3)
    assert data["failure"] is None  # the maximum is the specimen's, not a solver failure


def test_a_thin_balloon_has_its_limit_point_at_the_seventh_root_stretch():
    data = run(10.0, 0.1, 1.8, 32)
    assert data["converged"], data["failure"]
    limit = data["measured"]["limit_point"]
    assert closed_form_maximum(10.0, 0.1) == pytest.approx(7 ** (1 / 6), rel=1e-2)  # H/A = 0.01 is thin
    assert limit["stretch"] == pytest.approx(closed_form_maximum(10.0, 0.1), rel=5e-3)
    assert limit["stretch"] == pytest.approx(7 ** (1 / 6), rel=1.5e-2)


def test_a_mooney_rivlin_balloon_above_the_threshold_has_no_maximum():
    data = run(10.0, 0.5, 3.0, 20, "mooney-rivlin")
    assert data["converged"], data["failure"]
    p = data["curve"]["pressure"]
    assert all(b > a for a, b in zip(p, p[1:]))
    assert data["measured"]["limit_point"] is None and "no pressure maximum" in data["measured"]["limit_point_note"]


def test_the_octant_mesh_is_valid_counted_and_its_cavity_volume_exact():
    mesh = shell_mesh(2.0, 0.5, 0.5)
    check_mesh(mesh)
    from types import SimpleNamespace
    count = count_shell(SimpleNamespace(inner_radius=2.0, thickness=0.5), SimpleNamespace(size=0.5, order=1))
    assert (count.elements, count.nodes) == (mesh.t.shape[1], mesh.p.shape[1])
    # the facetted cavity: short of the octant of the sphere, converging to it as the mesh refines
    coarse, fine = cavity_volume(mesh, 2.0), cavity_volume(shell_mesh(2.0, 0.5, 0.25), 2.0)
    exact = math.pi / 6 * 8.0
    assert coarse < fine < exact and (exact - fine) < 0.3 * (exact - coarse)
    r = np.linalg.norm(mesh.p, axis=0)
    assert r.min() == pytest.approx(2.0) and r.max() == pytest.approx(2.5)


@pytest.mark.parametrize("test,field", [
    ({"stretch": 0.9}, "test.stretch"), ({"control": "pressure"}, "test.control"),
    ({"grips": "die"}, "test.grips"),
])
def test_a_bad_inflation_scene_names_its_field(test, field):
    with pytest.raises(SceneError, match=field.replace(".", r"\.")):
        parse_scene(scene(10.0, 1.0, 2.0, 4, test=test))


def test_under_pressure_control_the_balloon_stops_at_the_closed_form_pressure_maximum():
    """The pressure is prescribed past the maximum (1.27 p_max): no equilibrium exists beyond it,
    and the stop says so at the maximum's pressure (h = 2 mm: the cutbacks bracket it to
    Δp / 2⁵ = 1.6e-4 MPa, 0.3 %)."""
    raw = scene(10.0, 1.0, 2.0, 12, size=2.0, test={"control": "pressure", "pressure": 0.06})
    del raw["test"]["stretch"]
    raw["solver"] = {"max_cutbacks": 5, "max_iterations": 12}
    data = result_to_dict(run_scene(parse_scene(raw)))
    assert not data["converged"]
    reason = data["failure"]["reason"]
    assert reason.startswith("pressure maximum (limit point) of the specimen")
    lam_max = closed_form_maximum(10.0, 1.0)
    p_max = neo_hookean_thick(lam_max, 10.0, 1.0)
    p_stop = float(reason.split("no equilibrium above p = ")[1].split(" MPa")[0])
    assert p_stop == pytest.approx(p_max, rel=5e-3) and p_stop <= p_max * (1 + 1e-3)
    assert data["failure"]["last_converged_stretch"][0] == pytest.approx(p_stop)  # the control value is p
    stretch = float(reason.split("inner hoop stretch ")[1].split(" ")[0])
    assert 1.3 < stretch < lam_max  # on the rising branch, below the maximum's stretch (a flat top)
    # the recorded curve is the closed form's, read at the measured inner stretch
    c = data["curve"]
    closed = [neo_hookean_thick(lam, 10.0, 1.0) for lam in c["stretch"]]
    np.testing.assert_allclose(c["pressure"], closed, rtol=5e-3, atol=1e-3 * p_max)


def test_a_volume_cycle_passes_the_maximum_and_comes_back_down_the_same_curve():
    raw = scene(10.0, 1.0, 2.0, 10, size=2.0, test={"protocol": "cyclic", "amplitudes": [2.0]})
    del raw["test"]["stretch"]
    data = result_to_dict(run_scene(parse_scene(raw)))
    assert data["converged"], data["failure"]
    lam, p = np.array(data["curve"]["stretch"]), np.array(data["curve"]["pressure"])
    top = int(np.argmax(lam))
    assert lam[top] == pytest.approx(2.0) and lam[-1] == pytest.approx(1.0) and abs(p[-1]) < 1e-9
    for i in range(top + 1, len(lam)):  # elastic: down at the same stretch, the same pressure
        j = int(np.argmin(np.abs(lam[:top] - lam[i])))
        if abs(lam[j] - lam[i]) < 1e-12:
            assert p[i] == pytest.approx(p[j], rel=1e-6, abs=1e-9)
    assert data["measured"]["limit_point"] is not None


def test_a_pressure_cycle_is_refused():
    raw = scene(10.0, 1.0, 2.0, 10, test={"control": "pressure", "protocol": "cyclic", "amplitudes": [1.5]})
    del raw["test"]["stretch"]
    with pytest.raises(SceneError, match=r"test\.control"):
        parse_scene(raw)
