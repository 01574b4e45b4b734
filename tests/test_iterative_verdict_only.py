"""The iterative stability check when only the verdict is wanted (no ``[solver] eigenvalues``):
LOBPCG stops once the lowest pair's sign is decided (vlab.fe.eigen_amg), and must still give the
direct inertia's verdicts on the stability suite's hard cases; the eigenvalue it records is a
Rayleigh quotient (never below the true λ_min) within its residual of an eigenvalue."""

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp

from vlab.fe import eigen_amg, iterative
from vlab.fe.eigen_amg import amg_inertia
from vlab.fe.inertia import inertia
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.settings import using

from test_iterative_stability import BRANCH_SWITCH, CASES, ITERATIVE, _until_first_rejection

pytestmark = pytest.mark.skipif(iterative.available() is None, reason="pyamg not installed")


def _verdict_only(scene):
    return replace(scene, solver=replace(scene.solver, eigenvalues=False))


@pytest.mark.parametrize("name", [n for n in CASES if n not in BRANCH_SWITCH])
def test_the_verdict_only_check_gives_the_direct_verdicts(name):
    direct = result_to_dict(run_scene(CASES[name]))  # eigenvalues by shift-invert Lanczos
    with using(ITERATIVE):
        it = result_to_dict(run_scene(_verdict_only(CASES[name])))
    assert {s["stability_method"] for s in it["stability"]} == {"lobpcg-amg"}
    # every level up to the first rejection alike, that one for the same cause (its load may
    # differ: CG's inexact corrections change the substeps, as in test_iterative_stability)
    path = _until_first_rejection(direct), _until_first_rejection(it)
    assert [(a["t"], a["accepted"], bool(a["negative_eigenvalues"]), a["zero_eigenvalues"]) for a in path[0][:-1]] == \
           [(b["t"], b["accepted"], bool(b["negative_eigenvalues"]), b["zero_eigenvalues"]) for b in path[1][:-1]]
    a, b = path[0][-1], path[1][-1]
    assert (a["accepted"], a["limit_point"], bool(a["negative_eigenvalues"]), a["zero_eigenvalues"]) == \
           (b["accepted"], b["limit_point"], bool(b["negative_eigenvalues"]), b["zero_eigenvalues"])
    for a, b in zip(*path):
        assert b["eigenpair_residual"] <= eigen_amg.DECIDED_TOL
        if a["accepted"]:  # a Ritz value bounds λ_min from above (of a state that differs from
            # the direct path's by Newton's tolerance), and is decided positive
            assert b["lowest_eigenvalue"] >= a["lowest_eigenvalue"] * (1.0 - 1e-6) > 0.0
    assert (it["converged"], (it["failure"] or {}).get("reason", "")[:40]) == \
           (direct["converged"], (direct["failure"] or {}).get("reason", "")[:40])


@pytest.mark.parametrize("shift, negative", [(0.0, 0), (0.025, 1), (0.05, 3)])
def test_a_decided_pair_has_the_right_sign_and_lies_within_its_residual_of_an_eigenvalue(shift, negative):
    import pyamg

    L = pyamg.gallery.poisson((30, 30), format="csr")  # λ₁ ≈ 0.0205, λ₂ ≈ 0.0511
    K = (L - shift * sp.identity(L.shape[0])).tocsr()
    exact = np.linalg.eigvalsh(K.toarray())
    solver = iterative.AMGConjugateGradient(L, np.ones((L.shape[0], 1)))
    found = amg_inertia(K, solver, accurate=False)
    scale = float(np.max(np.abs(K.diagonal())))
    lowest, residual = found.lowest[0], found.residual * scale
    assert bool(found.negative) == (negative > 0) and inertia(K).positive_definite == found.positive_definite
    assert lowest >= exact[0] - 1e-12 and np.min(np.abs(exact - lowest)) <= residual
    assert residual <= eigen_amg.RESIDUAL_TOL * scale or abs(lowest) > eigen_amg.SIGN_MARGIN * residual


def test_the_verdict_only_check_stops_sooner_than_the_accurate_one(monkeypatch):
    import pyamg

    calls = []
    real = eigen_amg.spla.lobpcg

    def counted(*args, **kwargs):  # the iterations each call made
        w, X, history = real(*args, retResidualNormsHistory=True, **kwargs)
        calls.append(len(history))
        return w, X

    monkeypatch.setattr(eigen_amg.spla, "lobpcg", counted)
    L = pyamg.gallery.poisson((40, 40), format="csr")
    solver = iterative.AMGConjugateGradient(L, np.ones((L.shape[0], 1)))
    counts = {}
    for accurate in (True, False):
        calls.clear()
        solver.hierarchy.eigenvectors = None  # the same cold start for both
        found = amg_inertia(L, solver, accurate=accurate)
        counts[accurate] = sum(calls)
        assert found.positive_definite
    assert counts[False] < counts[True], counts
