"""Stability detection: inertia of K_ff, load limit points, inadmissible requests, restraint."""

import math

import numpy as np
import pytest
import scipy.sparse as sp

import vlab.loading.grips as grips_module
from helpers_scenes import block_scene
from vlab.fe.inertia import inertia, lowest_eigenpair
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.loading.restraint import unrestrained_modes


@pytest.mark.parametrize("seed", range(4))
def test_inertia_counts_negative_eigenvalues_like_a_dense_solver(seed):
    rng = np.random.default_rng(seed)
    A = sp.random(50, 50, density=0.1, random_state=seed)
    A = sp.csc_matrix(A + A.T + sp.diags(rng.normal(0.0, 0.5, 50)))
    dense = np.linalg.eigvalsh(A.toarray())
    got = inertia(A)
    assert got.negative == int(np.sum(dense < 0)) and got.zero == 0


def test_inertia_falls_back_when_the_diagonal_cannot_pivot_and_flags_zero_modes():
    swap = sp.csc_matrix(np.array([[0.0, 1.0], [1.0, 0.0]]))  # eigenvalues ±1, zero diagonal
    got = inertia(swap)
    assert (got.negative, got.zero, got.positive) == (1, 0, 1)
    singular = sp.csc_matrix(np.array([[1.0, 1.0], [1.0, 1.0]]))
    assert inertia(singular).zero == 1 and inertia(singular).positive_definite is False
    value, vector = lowest_eigenpair(swap)
    assert value == pytest.approx(-1.0) and np.linalg.norm(vector) == pytest.approx(1.0)


def test_rigid_body_restraint_is_checked_exactly():
    X = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    assert len(unrestrained_modes(X, np.array([], dtype=int))) == 6
    everything = np.arange(3 * len(X))
    assert unrestrained_modes(X, everything) == []
    x_faces = np.array([3 * n for n in range(len(X))])  # only u_x prescribed everywhere
    names = unrestrained_modes(X, x_faces)
    assert len(names) == 3 and any("translation along y" in n for n in names)


def test_missing_supports_are_reported_as_an_under_constrained_set_up(monkeypatch):
    monkeypatch.setattr(grips_module, "_rigid_body_supports", lambda *args: [])
    result = run_scene(block_scene("neo-hookean", 1.2))
    data = result_to_dict(result)
    assert not data["converged"] and data["curve"]["stress"] == []
    reason = data["failure"]["reason"]
    assert "under-constrained set-up" in reason
    assert "translation along y" in reason and "translation along z" in reason and "rotation about x" in reason


def test_stvk_tension_without_admissible_state_is_refused_before_solving():
    nu = 0.3
    data = result_to_dict(run_scene(block_scene("stvk", 2.2, nu=nu)))
    assert not data["converged"] and data["curve"]["stress"] == [] and data["stability"] == []
    reason = data["failure"]["reason"]
    assert "no admissible state beyond stretch" in reason
    assert f"{math.sqrt(1 + 1 / nu):.6g}" in reason  # sqrt(1 + 1/nu) = 2.08167
    # the volumetric StVK and Neo-Hookean have a (stable) state there and carry on
    for model in ("stvk-volumetric", "neo-hookean"):
        other = result_to_dict(run_scene(block_scene(model, 2.2, steps=4)))
        assert other["converged"] and other["curve"]["stretch"][-1] == pytest.approx(2.2)
        assert all(s["negative_eigenvalues"] == 0 for s in other["stability"])


def test_stvk_compression_stops_at_its_limit_point_while_nh_and_stvk_volumetric_carry_on():
    # One hexahedron cannot buckle, so the homogeneous load maximum at 1/sqrt(3) shows alone.
    runs = {m: result_to_dict(run_scene(block_scene(m, 0.3, size=10.0, steps=70)))
            for m in ("stvk", "stvk-volumetric", "neo-hookean")}
    stvk = runs["stvk"]
    assert not stvk["converged"]
    reason = stvk["failure"]["reason"]
    assert reason.startswith("load limit point beyond stretch") and "no longer rises" in reason
    # cutbacks bracket the load maximum: last accepted state and first rejected one
    last_ok, rejected = stvk["failure"]["last_converged_stretch"][0], stvk["failure"]["stretch"][0]
    assert rejected <= 1 / math.sqrt(3) <= last_ok and last_ok - rejected < 0.005
    assert min(stvk["curve"]["stretch"]) >= last_ok  # states past the limit are never returned
    assert stvk["stability"][-1]["limit_point"] and not stvk["stability"][-1]["accepted"]
    for model in ("stvk-volumetric", "neo-hookean"):
        assert runs[model]["converged"] and runs[model]["curve"]["stretch"][-1] == pytest.approx(0.3)
        assert all(s["negative_eigenvalues"] == 0 and s["accepted"] for s in runs[model]["stability"])


def test_loss_of_positive_definiteness_stops_stvk_before_its_limit_point_on_a_finer_mesh():
    runs = {m: result_to_dict(run_scene(block_scene(m, 0.62, size=2.5, steps=10)))
            for m in ("stvk", "stvk-volumetric", "neo-hookean")}
    stvk = runs["stvk"]
    rejected = stvk["stability"][-1]
    assert not stvk["converged"] and "loss of stability" in stvk["failure"]["reason"]
    assert rejected["negative_eigenvalues"] > 0 and not rejected["accepted"]
    assert all((s["negative_eigenvalues"] == 0) == s["accepted"] for s in stvk["stability"])
    for model in ("stvk-volumetric", "neo-hookean"):
        assert runs[model]["converged"]
        assert all(s["negative_eigenvalues"] == 0 for s in runs[model]["stability"])


def test_near_incompressible_displacement_only_run_warns_about_locking(caplog):
    # clamped grips: the roller block's uniform field cannot lock and does not warn (test_locking_warning.py)
    data = result_to_dict(run_scene(block_scene("neo-hookean", 1.1, grips="clamped", nu=0.49, size=10.0, steps=2)))
    assert any("volumetric locking" in w for w in data["warnings"])
    assert any("volumetric locking" in r.getMessage() for r in caplog.records)
    assert result_to_dict(run_scene(block_scene("neo-hookean", 1.1, grips="clamped", nu=0.3, size=10.0,
                                                steps=2)))["warnings"] == []
