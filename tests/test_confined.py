"""Confined compression in a frictionless rigid die (vlab.loading.kinds.confined) on the cylinder
(vlab.geometry.cylinder) and the block: the homogeneous state F = diag(λ, 1, 1) of every model to
1e-9 (the reference computed here from each model's P(F), not from the kind's oracle), the moduli
it measures against the input's K and M = K + 4G/3, the cylinder's mesh and the grammar."""

from __future__ import annotations

import math
from functools import cache
from types import SimpleNamespace

import numpy as np
import pytest
import skfem

from vlab.geometry.cylinder import count_cylinder, cylinder_mesh, section_area
from vlab.geometry.mesh_check import check_mesh
from vlab.materials import build_material
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import MODELS, SPRING_NETWORK, SceneError, parse_scene

CONTINUUM = [m for m in MODELS if m != SPRING_NETWORK]
LAMBDA = 0.85

try:
    from rubber_cards import CARDS as RUBBER_CARDS
except ImportError:
    RUBBER_CARDS = {}


def card(model: str) -> dict:
    return ({k: v for k, v in RUBBER_CARDS[model].items() if k != "model"} | {"K": 20.0}
            if model in RUBBER_CARDS else {"E": 10.0, "nu": 0.3})


def scene(model: str, specimen: dict | None = None, test: dict | None = None, mesh: dict | None = None) -> dict:
    return {"name": "die", "specimen": specimen or {"shape": "cylinder", "radius": 2.0, "length": 3.0},
            "mesh": {"size": 1.0, "cell": "hex"} | (mesh or {}),
            "material": {"model": model} | card(model), "solver": {"rtol": 1e-12},
            "test": {"kind": "confined-compression", "grips": "die", "stretch": LAMBDA, "steps": 3} | (test or {})}


@cache
def run(model: str, shape: str = "cylinder") -> dict:
    specimen = None if shape == "cylinder" else {"shape": "block", "size": [3.0, 2.0, 2.0]}
    parsed = parse_scene(scene(model, specimen))
    return result_to_dict(run_scene(parsed)) | {"_scene": parsed}


@pytest.mark.parametrize("shape", ["cylinder", "block"])
@pytest.mark.parametrize("model", CONTINUUM)
def test_every_model_in_the_die_is_the_homogeneous_state_diag_lambda_1_1_to_1e_9(model, shape):
    data = run(model, shape)
    assert data["converged"], data["failure"]
    material = build_material(data["_scene"].material)
    curve = data["curve"]
    for lam, stress, J, p in zip(curve["stretch"], curve["stress"], curve["volume_ratio"], curve["pressure"]):
        F = np.diag([lam, 1.0, 1.0])
        P = np.asarray(material.stress(F))
        sigma = P @ F.T / lam
        assert abs(stress - P[0, 0]) <= 1e-9 * max(abs(P[0, 0]), 1e-12), (lam, stress, P[0, 0])
        assert abs(J - lam) <= 1e-12
        assert abs(p + np.trace(sigma) / 3) <= 1e-9 * abs(P[0, 0])
    assert curve["stretch"][-1] == pytest.approx(LAMBDA)
    assert data["reference"]["max_relative_error_x"] < 1e-9


def test_the_die_measures_the_bulk_and_constrained_moduli_of_the_input():
    data = run("neo-hookean")
    K, mu = data["input"]["K"], data["input"]["mu"]
    measured = data["measured"]
    assert data["measured"]["E"] is None and data["measured"]["nu"] is None  # not what a die measures
    # the window 0.05–0.25 % strain: the secant of a curve whose slope changes by O(ε) of itself
    assert measured["bulk_modulus"] == pytest.approx(K, rel=5e-3)
    assert measured["constrained_modulus"] == pytest.approx(K + 4 * mu / 3, rel=5e-3)
    assert measured["G_derived"] == pytest.approx(mu, rel=3e-2)


def test_the_cylinder_mesh_is_valid_and_counted_before_it_is_built():
    mesh = cylinder_mesh(2.0, 3.0, 0.5)
    check_mesh(mesh)
    volume = skfem.Basis(mesh, skfem.ElementHex1()).dx.sum()
    assert volume == pytest.approx(section_area(2.0, 0.5) * 3.0, rel=1e-12)  # the inscribed polygon, swept
    assert section_area(2.0, 0.5) == pytest.approx(math.pi * 4.0, rel=2e-2)
    for order in (1, 2):
        count = count_cylinder(SimpleNamespace(radius=2.0, length=3.0), SimpleNamespace(size=0.5, order=order,
                                                                                        cell="hex"))
        assert count.elements == mesh.t.shape[1]
        if order == 1:
            assert count.nodes == mesh.p.shape[1]
    r = np.hypot(mesh.p[1], mesh.p[2])
    on_surface = np.abs(r - 2.0) < 1e-9
    assert on_surface.sum() > 0 and r.max() <= 2.0 * (1 + 1e-12)


@pytest.mark.parametrize("test,mesh,field", [
    ({"stretch": 1.1}, {}, "test.stretch"),
    ({"stretch": [0.9, 0.9]}, {}, "test.stretch"),
    ({"grips": "roller"}, {}, "test.grips"),
    ({}, {"cell": "quad"}, "mesh.cell"),
])
def test_a_bad_die_scene_names_its_field(test, mesh, field):
    with pytest.raises(SceneError, match=field.replace(".", r"\.")):
        raw = scene("neo-hookean", test=test, mesh=mesh)
        run_scene(parse_scene(raw))


def test_the_cylinder_refuses_a_kind_it_cannot_run():
    with pytest.raises(SceneError, match=r"test\.kind"):
        parse_scene(scene("neo-hookean", test={"kind": "uniaxial", "grips": "roller", "stretch": 1.1}))
