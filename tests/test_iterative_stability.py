"""The stability check that scales (#20): LOBPCG on the CG's AMG hierarchy agrees with the direct
inertia (same verdicts, lowest eigenvalue to 1e-6), the hierarchy is reused and rebuilt only on a
slowdown, and results.json says which method vetted each state."""

import json

import numpy as np
import pytest
import scipy.sparse as sp

from vlab.fe import iterative
from vlab.fe.eigen_amg import amg_inertia
from vlab.fe.inertia import inertia
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import parse_scene
from vlab.settings import Settings, using

pytestmark = pytest.mark.skipif(iterative.available() is None, reason="pyamg not installed")
ITERATIVE = Settings(iterative_from=0)  # CG + AMG and LOBPCG on any 3D mesh


def _block(model, stretch, grips="roller", size=2.5, steps=10, extent=(10.0, 10.0, 10.0), **solver):
    return parse_scene({"name": "b", "specimen": {"shape": "block", "size": list(extent)},
                        "mesh": {"size": size, "cell": "hex"}, "material": {"model": model, "E": 10.0, "nu": 0.3},
                        "test": {"kind": "uniaxial", "grips": grips, "stretch": stretch, "steps": steps},
                        "measure": {"modulus_points": 0}, "solver": {"eigenvalues": True, **solver}})


def _both(scene):
    direct = result_to_dict(run_scene(scene))
    with using(ITERATIVE):
        it = result_to_dict(run_scene(scene))
    return direct, it


CASES = {  # the stability suite's verdicts on meshes small enough for both paths
    "stable compression": _block("neo-hookean", 0.3, size=10.0, steps=70),
    "block buckling in two modes": _block("neo-hookean", 0.3, steps=20),
    "StVK limit point": _block("stvk", 0.3, size=10.0, steps=70),
    "loss of ellipticity": _block("stvk", 0.5, grips="clamped", steps=10),
    "buckling strip": _block("neo-hookean", 0.9, grips="clamped", size=0.5, steps=4, extent=(10.0, 2.0, 1.0)),
}


#: a perfect strip at its symmetric bifurcation: after the first unstable state, the cut-back
#: substeps of the iterative path (inexact CG corrections, not symmetric to round-off) may settle
#: on the stable buckled branch where the direct path stays on the fundamental one and stops
BRANCH_SWITCH = {"buckling strip"}


def _until_first_rejection(data: dict) -> list[dict]:
    records = data["stability"]
    first = next((i for i, s in enumerate(records) if not s["accepted"]), len(records) - 1)
    return records[:first + 1]


@pytest.mark.parametrize("name", list(CASES))
def test_the_iterative_check_gives_the_direct_verdicts_and_lowest_eigenvalues(name):
    direct, it = _both(CASES[name])
    assert it["solver"]["linear"]["newton"] == "cg-amg" and it["solver"]["linear"]["amg_setups"] >= 1
    assert {s["stability_method"] for s in it["stability"]} == {"lobpcg-amg"}
    assert "lobpcg-amg" not in {s["stability_method"] for s in direct["stability"]}
    assert all(s["eigenpair_residual"] <= 1e-5 for s in it["stability"])  # (eigen_amg.DECIDED_TOL)
    # every scheduled level up to the first rejected state alike (load, verdict, lowest
    # eigenvalue); the first rejection for the same cause (its load may differ: the substeps
    # grow after easy Newton solves, and CG's iteration counts differ from the direct ones)
    path = _until_first_rejection(direct), _until_first_rejection(it)
    assert len(path[0]) == len(path[1])
    for a, b in zip(path[0][:-1], path[1][:-1]):
        assert (a["t"], a["accepted"], b["accepted"], a["negative_eigenvalues"], b["negative_eigenvalues"]) == \
               (b["t"], True, True, 0, 0)
        assert b["lowest_eigenvalue"] == pytest.approx(a["lowest_eigenvalue"], rel=1e-6)
    a, b = path[0][-1], path[1][-1]
    assert (a["accepted"], a["limit_point"], bool(a["negative_eigenvalues"]), a["zero_eigenvalues"]) == \
           (b["accepted"], b["limit_point"], bool(b["negative_eigenvalues"]), b["zero_eigenvalues"])
    if a["t"] == b["t"]:
        assert b["lowest_eigenvalue"] == pytest.approx(a["lowest_eigenvalue"], rel=1e-6)
    if name in BRANCH_SWITCH:
        return
    assert it["converged"] == direct["converged"]
    assert (it["failure"] or {}).get("reason", "")[:40] == (direct["failure"] or {}).get("reason", "")[:40]
    if direct["critical"] is not None:  # the bracketing's end: the last stable and an unstable state
        c, d = direct["critical"], it["critical"]
        assert (d["kind"], d["stretch_stable"]) == (c["kind"], c["stretch_stable"])
        assert d["eigenvalue_stable"] == pytest.approx(c["eigenvalue_stable"], rel=1e-6)
        assert d["eigenvalue_unstable"] < 0 and c["eigenvalue_unstable"] < 0


def test_lobpcg_declares_an_indefinite_matrix_unstable_and_a_definite_one_stable():
    import pyamg

    L = pyamg.gallery.poisson((30, 30), format="csr")
    for shift, negative in ((0.0, 0), (0.05, 3)):  # λ_min(L) ≈ 0.021: the shift makes 3 negative
        K = (L - shift * sp.identity(L.shape[0])).tocsr()
        exact = np.linalg.eigvalsh(K.toarray())
        solver = iterative.AMGConjugateGradient(L, np.ones((L.shape[0], 1)))
        found = amg_inertia(K, solver)
        assert found.method == "lobpcg-amg" and bool(found.negative) == (negative > 0)
        assert found.lowest[0] == pytest.approx(exact[0], rel=1e-6)
        assert inertia(K).positive_definite == found.positive_definite


def test_cg_s_negative_curvature_is_kept_as_a_witness_and_starts_the_check():
    import pyamg

    L = pyamg.gallery.poisson((20, 20), format="csr")
    K = (L - 0.3 * sp.identity(L.shape[0])).tocsr()
    solver = iterative.AMGConjugateGradient(K, np.ones((K.shape[0], 1)))
    with pytest.raises(iterative.IterativeSolveFailed):
        solver.solve(np.random.default_rng(0).standard_normal(K.shape[0]))
    w = solver.hierarchy.witness
    assert w is not None and w @ (K @ w) <= 0.0
    found = amg_inertia(K, solver)
    assert found.negative >= 1 and found.lowest[0] <= w @ (K @ w) / (w @ w)


def test_one_amg_hierarchy_serves_the_whole_run_and_reuse_gives_the_same_state(monkeypatch):
    scene = _block("neo-hookean", 1.4, grips="clamped", size=1.0, steps=4, extent=(4.0, 3.0, 3.0), rtol=1e-10)
    with using(ITERATIVE):
        reused = run_scene(scene)
        monkeypatch.setattr(iterative.AMGHierarchy, "stale", property(lambda self: True, lambda self, v: None),
                            raising=False)
        fresh = run_scene(scene)
    assert reused.converged and fresh.converged
    setups = reused.diagnostics.linear_solver["amg_setups"], fresh.diagnostics.linear_solver["amg_setups"]
    assert setups[0] <= 2 < 8 <= setups[1], setups
    np.testing.assert_allclose(reused.curve.force[0], fresh.curve.force[0], rtol=1e-8)


def test_a_measured_cg_slowdown_marks_the_hierarchy_for_a_rebuild():
    h = iterative.AMGHierarchy(None)
    h.stale = False
    h.record(10, 10.0)  # baseline: one iteration per decade
    h.record(16, 10.0)
    assert not h.stale
    h.record(20, 10.0)  # 2 per decade > 1.75 × baseline
    assert h.stale


def test_results_json_carries_the_method_counts_and_per_phase_peak_memory(tmp_path):
    from vlab.report.writer import ReportOptions, write_run

    with using(ITERATIVE):
        data = write_run(run_scene(_block("neo-hookean", 1.2, steps=3)), tmp_path / "r", None,
                         ReportOptions(vtu=False, render=False))
    saved = json.loads((tmp_path / "r" / "results.json").read_text())
    assert saved["solver"]["linear"]["stability_methods"] == {"lobpcg-amg": len(saved["stability"])}
    assert saved["solver"]["linear"]["amg_setups"] >= 1
    peaks = saved["timing"]["peak_memory_mb"]
    assert {"assembly", "linear_solve", "stability_check", "measurement", "run"} <= set(peaks)
    assert all(0 < v <= peaks["run"] for v in peaks.values()), sorted(peaks.items())
    assert data["stability"][0]["stability_method"] == "lobpcg-amg"


def test_small_problems_stay_on_the_direct_path_by_default():
    data = result_to_dict(run_scene(_block("neo-hookean", 1.2, steps=2)))
    assert data["solver"]["linear"]["newton"] == "direct" and data["solver"]["linear"]["amg_setups"] == 0
    assert {s["stability_method"] for s in data["stability"]} <= {"cholesky", "ldlt-inertia"}
