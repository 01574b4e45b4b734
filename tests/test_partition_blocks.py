"""Partition's gathers give exactly the dense blocks of an assembled tangent, and K is symmetric,
so the grips' rows K[g, free] are rows of K_fpᵀ (vlab.identify.fe_levels reads them so: the
tangents keep their blocks, not the full K)."""

import numpy as np

from vlab.fe.assembly import Partition
from vlab.fe.space import DisplacementSpace
from vlab.fe.problem import HyperelasticBody
from vlab.materials import make_material


def test_the_three_blocks_are_the_dense_ones_and_the_grip_rows_follow_by_symmetry():
    import skfem

    mesh = skfem.MeshHex.init_tensor(np.linspace(0, 2, 3), np.linspace(0, 1, 3), np.linspace(0, 1, 2))
    space = DisplacementSpace.build(mesh, 1)
    body = HyperelasticBody(space, make_material("neo-hookean", lmbda=5.769, mu=3.846))
    rng = np.random.default_rng(3)
    K = body.stiffness(body.evaluate(0.05 * rng.standard_normal(space.n_dofs))).tocsr()
    prescribed = np.array([0, 3, 4, 5, 11, 20, 31])
    part = Partition.build(body.pattern, prescribed)
    Kff, Kfp = part.blocks(K)
    Kpp = part.prescribed_block(K)
    A, f = K.toarray(), part.free
    np.testing.assert_array_equal(Kff.toarray(), A[np.ix_(f, f)])
    np.testing.assert_array_equal(Kfp.toarray(), A[np.ix_(f, prescribed)])
    np.testing.assert_array_equal(Kpp.toarray(), A[np.ix_(prescribed, prescribed)])
    grip = prescribed[[1, 4]]
    rows = Kfp.T.tocsr()[[1, 4]].toarray()
    np.testing.assert_allclose(rows, A[np.ix_(grip, f)], rtol=0, atol=1e-12 * np.abs(A).max())
    # the path slope by blocks equals vᵀKv with the full K
    up = rng.standard_normal(len(prescribed))
    vf = rng.standard_normal(len(f))
    v = np.zeros(space.n_dofs)
    v[f], v[prescribed] = vf, up
    by_blocks = vf @ (Kff @ vf) + 2.0 * vf @ (Kfp @ up) + up @ (Kpp @ up)
    np.testing.assert_allclose(by_blocks, v @ (K @ v), rtol=1e-12)
