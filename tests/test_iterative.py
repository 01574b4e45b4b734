"""CG + AMG Newton corrections: same answer as the direct path, honest failure on indefinite K."""

import numpy as np
import pytest
import scipy.sparse as sp

import dataclasses

from vlab.fe import iterative, linsolve, pardiso
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene

pytestmark = pytest.mark.skipif(iterative.available() is None, reason="pyamg not installed")


def _scene(linear: str):
    return parse_scene({
        "name": "amg", "specimen": {"shape": "block", "size": [4.0, 3.0, 3.0]},
        "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "grips": "clamped", "stretch": 1.4, "steps": 4},
        "measure": {"modulus_points": 0}, "solver": {"linear": linear, "rtol": 1e-10},
    })


def test_cg_amg_newton_reaches_the_direct_solution():
    direct, cg = run_scene(_scene("direct")), run_scene(_scene("cg-amg"))
    assert direct.converged and cg.converged
    assert cg.diagnostics.linear_solver["newton"] == "cg-amg"
    np.testing.assert_allclose(cg.curve.force[0], direct.curve.force[0], rtol=1e-8)


def test_rigid_body_modes_are_in_the_nullspace_of_an_unconstrained_stiffness():
    from vlab.fe.problem import HyperelasticBody
    from vlab.fe.space import DisplacementSpace
    from vlab.geometry.block import block_mesh
    from vlab.materials import make_material

    space = DisplacementSpace.build(block_mesh((2.0, 1.0, 1.0), 0.5, "tet"), 1)
    body = HyperelasticBody(space, make_material("linear", 5.0, 2.0))
    K = body.stiffness(body.evaluate(np.zeros(space.n_dofs)))
    B = iterative.rigid_body_modes(space.node_coordinates)
    assert np.abs(K @ B).max() <= 1e-10 * abs(K).max() * np.abs(B).max()


def test_cg_detects_an_indefinite_matrix_instead_of_returning_garbage():
    import pyamg

    L = pyamg.gallery.poisson((20, 20), format="csr")
    K = (L - 0.3 * sp.identity(L.shape[0])).tocsr()  # a few negative eigenvalues
    assert np.linalg.eigvalsh(K.toarray()).min() < 0
    solver = iterative.AMGConjugateGradient(K, np.ones((K.shape[0], 1)))
    b = np.random.default_rng(0).standard_normal(K.shape[0])
    with pytest.raises(iterative.IterativeSolveFailed):
        solver.solve(b)


def test_auto_chooses_by_the_measured_crossover():
    assert iterative.choose("auto", 1_000, "pardiso") == "direct"
    assert iterative.choose("auto", 10**6, "pardiso") == "cg-amg"
    assert iterative.choose("auto", iterative.CROSSOVER["superlu"], "superlu") == "cg-amg"
    assert iterative.choose("direct", 10**6, "superlu") == "direct"


def _never():
    raise AssertionError("the factorization's cost was asked for where the DOF rule decides")


def test_auto_keeps_the_direct_path_where_a_factorization_is_cheap_for_the_mesh_shape(monkeypatch):
    from vlab.fe.pardiso import FactorCost

    n = 50_000
    nnz = 64 * n
    shell = FactorCost(15_000_000, int(2_811 * nnz / 1e6), nnz)  # the sphere octant's ratio
    solid = FactorCost(38_000_000, int(14_148 * nnz / 1e6), nnz)  # the torsion cylinder's
    choice = iterative.decide("auto", n, "pardiso", cost=lambda: shell)
    assert choice.path == "direct" and "2,811 flops per entry of K_ff ≤ 10,000" in choice.reason
    choice = iterative.decide("auto", n, "pardiso", cost=lambda: solid)
    assert choice.path == "cg-amg" and "> 10,000" in choice.reason
    assert iterative.decide("auto", n, "pardiso", cost=lambda: None).path == "cg-amg"
    monkeypatch.setattr(iterative, "_available_memory", lambda: 2 * 8 * 15_000_000 * 1.9)
    choice = iterative.decide("auto", n, "pardiso", cost=lambda: shell)
    assert choice.path == "cg-amg" and "does not fit" in choice.reason
    # where the DOF count decides, nothing is analysed
    assert iterative.decide("auto", 1_000, "pardiso", cost=_never).path == "direct"
    assert iterative.decide("auto", n, "superlu", cost=_never).path == "cg-amg"
    assert iterative.decide("auto", iterative.ANALYSE_UP_TO + 1, "pardiso", cost=_never).path == "cg-amg"
    assert iterative.decide("direct", n, "pardiso", cost=_never).reason == "solver.linear = 'direct'"


def test_a_set_crossover_is_obeyed_without_asking_for_the_cost():
    from vlab import settings

    before = settings.current()
    settings.use(dataclasses.replace(before, iterative_from=0))
    try:
        assert iterative.decide("auto", 10, "pardiso", cost=_never).path == "cg-amg"
    finally:
        settings.use(before)


@pytest.mark.skipif(pardiso.library() is None, reason="PARDISO (vlab[fast]) not installed")
def test_a_thin_plate_fills_less_per_entry_than_a_cube_and_a_run_records_why(monkeypatch):
    """Nested dissection fills a plate like a 2D mesh: fewer factorization flops per stored entry
    than a cube of fewer DOFs (the ratio grows with n, as n^(1/2) in 2D and n in 3D: on the node
    graph 615 against 1,310 here (10,086 and 3,993 DOFs), on K_ff 2,811 against 12,112 at
    ~45,000 DOFs). With the DOF crossover lowered to this test's size, the run asks PARDISO's
    analysis and records the path and the reason in results.json."""
    linsolve.use_solver("pardiso")
    try:
        plate = _run_kind({"shape": "block", "size": [40.0, 40.0, 1.0]}, 1.0, monkeypatch)
        cube = _run_kind({"shape": "block", "size": [10.0, 10.0, 10.0]}, 1.0, monkeypatch)
    finally:
        linsolve.use_solver("auto")
    ratio = {name: float(r.diagnostics.linear_solver["choice"].split("GFLOP per factorization, ~")[1]
                         .split(" flops")[0].replace(",", "")) for name, r in (("plate", plate), ("cube", cube))}
    assert plate.space.n_dofs > 2 * cube.space.n_dofs
    assert ratio["plate"] < ratio["cube"], ratio
    assert plate.diagnostics.linear_solver["newton"] == "direct"
    from vlab.report.results import result_to_dict
    from vlab.report.table_rows import summary_rows

    shown = dict(summary_rows(result_to_dict(plate)))["linear solver; tangent kernel"]
    assert "flops per entry of K_ff ≤ 10,000" in shown  # the report says why


def _run_kind(specimen: dict, h: float, monkeypatch):
    monkeypatch.setitem(iterative.CROSSOVER, "pardiso", 0)
    scene = parse_scene({
        "name": "fill", "specimen": specimen, "mesh": {"size": h, "cell": "hex"},
        "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.1, "steps": 1},
        "measure": {"modulus_points": 0}})
    result = run_scene(scene)
    assert result.converged
    return result


def test_unknown_linear_solver_is_rejected_naming_the_field():
    with pytest.raises(SceneError, match="solver.linear"):
        _scene("gmres")
