"""Assembly kernels: the fast reference-cell stiffness equals the textbook contraction and the
derivative of the internal force, on distorted meshes of every element type."""

import numpy as np
import pytest
import skfem

from vlab.fe import assembly
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.geometry.block import block_mesh
from vlab.materials import make_material

CASES = [("hex", 1), ("hex", 2), ("tet", 1), ("tet", 2)]


def _space(cell: str, order: int) -> DisplacementSpace:
    mesh = block_mesh((2.0, 1.5, 1.0), 0.5, cell)
    distorted = mesh.p + 0.04 * np.sin(3.0 * mesh.p[[1, 2, 0]])  # curved, non-affine cells
    return DisplacementSpace.build(type(mesh)(distorted, mesh.t), order)


@pytest.mark.parametrize("cell,order", CASES)
def test_reference_map_reproduces_gradients(cell, order):
    space = _space(cell, order)
    assert space.reference_dN is not None
    rebuilt = np.einsum("qam,mJeq->eqaJ", space.reference_dN, space.inverse_jacobian)
    np.testing.assert_allclose(rebuilt, space.dN, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("cell,order", CASES)
def test_fast_stiffness_equals_textbook_contraction(cell, order):
    space = _space(cell, order)
    material = make_material("neo-hookean", 5.0, 2.0)
    u = 0.02 * np.random.default_rng(1).standard_normal(space.n_dofs)
    A = material.tangent(space.deformation_gradient(u))
    textbook = np.einsum("eqaJ,iJkLeq,eqbL,eq->ikeab", space.dN, A, space.dN, space.dx)
    for kernel in (assembly.element_stiffness, assembly._element_stiffness_generic):
        Ke = kernel(space, A)
        assert Ke.shape == textbook.shape
        np.testing.assert_allclose(Ke, textbook, rtol=0, atol=1e-12 * np.abs(textbook).max())


@pytest.mark.parametrize("model", ["neo-hookean", "stvk", "linear"])
@pytest.mark.parametrize("cell,order", CASES)
def test_tangent_terms_pulled_back_equal_the_full_tangent_kernel(cell, order, model):
    space = _space(cell, order)
    material = make_material(model, 5.0, 2.0)
    F = space.deformation_gradient(0.02 * np.random.default_rng(3).standard_normal(space.n_dofs))
    terms = material.tangent_terms(F)
    np.testing.assert_allclose(terms.full(), material.tangent(F), rtol=0, atol=1e-13)
    textbook = np.einsum("eqaJ,iJkLeq,eqbL,eq->ikeab", space.dN, material.tangent(F), space.dN,
                         space.dx)
    Ke = assembly.element_stiffness(space, terms)
    np.testing.assert_allclose(Ke, textbook, rtol=0, atol=1e-12 * np.abs(textbook).max())
    pattern = assembly.SparsityPattern.build(space.element_nodes)  # any memory layout scatters alike
    K_fast, K_copy = pattern.matrix(Ke), pattern.matrix(np.ascontiguousarray(Ke))
    assert abs(K_fast - K_copy).max() <= 1e-14 * abs(K_copy).max()


@pytest.mark.parametrize("cell,order", [("hex", 1), ("tet", 2)])
def test_stiffness_is_the_derivative_of_the_internal_force(cell, order):
    space = _space(cell, order)
    body = HyperelasticBody(space, make_material("neo-hookean", 5.0, 2.0))
    rng = np.random.default_rng(2)
    u = 0.02 * rng.standard_normal(space.n_dofs)
    du = rng.standard_normal(space.n_dofs)
    ev = body.evaluate(u)
    K = body.stiffness(ev)
    h = 1e-6
    fd = (body.evaluate(u + h * du).f_int - body.evaluate(u - h * du).f_int) / (2 * h)
    np.testing.assert_allclose(K @ du, fd, rtol=0, atol=1e-6 * np.abs(fd).max())
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()


def test_no_reference_map_falls_back_to_generic_kernel():
    space = _space("hex", 1)
    plain = DisplacementSpace(space.basis, space.element_nodes, space.dN, space.dx)
    A = make_material("stvk", 5.0, 2.0).tangent(plain.deformation_gradient(np.zeros(plain.n_dofs)))
    np.testing.assert_allclose(assembly.element_stiffness(plain, A),
                               assembly.element_stiffness(space, A), atol=1e-12)


def test_sparsity_pattern_covers_every_element_coupling():
    mesh = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 3)] * 3)
    space = DisplacementSpace.build(mesh, 1)
    pattern = assembly.SparsityPattern.build(space.element_nodes)
    n_el, n_loc = space.element_nodes.shape
    K = pattern.matrix(np.ones((3, 3, n_el, n_loc, n_loc)))
    assert K.shape == (space.n_dofs, space.n_dofs)
    assert abs(K - K.T).max() == 0
    # each diagonal entry counts the elements sharing that node
    shared = np.bincount(space.element_nodes.ravel(), minlength=space.n_nodes)
    np.testing.assert_array_equal(K.diagonal(), np.repeat(shared, 3))


@pytest.mark.parametrize("model", ["neo-hookean", "stvk", "linear"])
@pytest.mark.parametrize("cell,order", CASES)
def test_symmetric_assembly_of_six_blocks_equals_the_full_scatter(cell, order, model):
    """The body's stiffness (blocks i ≤ k scattered, i > k mirrored) is the textbook K."""
    space = _space(cell, order)
    material = make_material(model, 5.0, 2.0)
    body = HyperelasticBody(space, material)
    ev = body.evaluate(0.02 * np.random.default_rng(4).standard_normal(space.n_dofs))
    textbook = np.einsum("eqaJ,iJkLeq,eqbL,eq->ikeab", space.dN, material.tangent(ev.F), space.dN,
                         space.dx)
    K_full = body.pattern.matrix(np.ascontiguousarray(textbook))
    K = body.stiffness(ev)
    assert K.has_sorted_indices and np.array_equal(K.indptr, K_full.indptr)
    assert abs(K - K_full).max() <= 1e-12 * abs(K_full).max()


@pytest.mark.parametrize("dim", [3, 2])
def test_sparsity_pattern_from_node_pairs_equals_the_dof_pattern(dim):
    """The CSR built from node pairs is the sorted, duplicate-free DOF pattern of the elements,
    and ``slot`` sends every element entry (i, k, e, a, b) to the CSR index of its DOF pair."""
    rng = np.random.default_rng(5)
    nodes = np.array([rng.choice(40, size=6, replace=False) for _ in range(30)])
    nodes[0, 0] = 39  # the largest node is used
    pattern = assembly.SparsityPattern.build(nodes, dim)
    comp = np.arange(dim)
    rows = dim * nodes[None, None, :, :, None] + comp[:, None, None, None, None]
    cols = dim * nodes[None, None, :, None, :] + comp[None, :, None, None, None]
    rows, cols = (a.ravel() for a in np.broadcast_arrays(rows, cols))
    expected = sorted(set(zip(rows.tolist(), cols.tolist())))
    csr_rows = np.repeat(np.arange(pattern.n), np.diff(pattern.indptr))
    assert list(zip(csr_rows.tolist(), pattern.indices.tolist())) == expected
    np.testing.assert_array_equal(csr_rows[pattern.slot], rows)
    np.testing.assert_array_equal(pattern.indices[pattern.slot], cols)
