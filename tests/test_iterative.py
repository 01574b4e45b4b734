"""CG + AMG Newton corrections: same answer as the direct path, honest failure on indefinite K."""

import numpy as np
import pytest
import scipy.sparse as sp

from vlab.fe import iterative
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


def test_unknown_linear_solver_is_rejected_naming_the_field():
    with pytest.raises(SceneError, match="solver.linear"):
        _scene("gmres")
