"""Point location and the probe matrix against scikit-fem's own element finder and probes, and
against functions the elements interpolate exactly."""

import numpy as np
import pytest
import skfem

from vlab.geometry.locate import locate
from vlab.fe.space import DisplacementSpace

rng = np.random.default_rng(3)


def _distorted(mesh, amount):
    """The mesh (of cells of width h) with its interior vertices moved randomly by up to
    ``amount`` × h/2 along each axis (the boundary kept): non-planar faces, still valid cells."""
    p = mesh.p.copy()
    h = np.ptp(p[0]) / (len(np.unique(p[0])) - 1)
    interior = np.setdiff1d(np.arange(mesh.nvertices), mesh.boundary_nodes())
    p[:, interior] += amount * h / 2 * rng.uniform(-1, 1, (mesh.dim(), len(interior)))
    return type(mesh)(p, mesh.t)


MESHES = {
    "hex": lambda: _distorted(skfem.MeshHex.init_tensor(*[np.linspace(0, 1, 5)] * 3), 0.5),
    "tet": lambda: _distorted(skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 5)] * 3), 0.3),
    "quad": lambda: _distorted(skfem.MeshQuad.init_tensor(*[np.linspace(0, 1, 6)] * 2), 0.5),
    "tri": lambda: _distorted(skfem.MeshTri.init_tensor(*[np.linspace(0, 1, 6)] * 2), 0.3),
}
ELEMENTS = {"hex": (skfem.ElementHex1, skfem.ElementHex2), "tet": (skfem.ElementTetP1, skfem.ElementTetP2),
            "quad": (skfem.ElementQuad1, skfem.ElementQuad2), "tri": (skfem.ElementTriP1, skfem.ElementTriP2)}


def _space(basis):
    space = DisplacementSpace.__new__(DisplacementSpace)  # only the scalar basis is read
    object.__setattr__(space, "basis", basis)
    return space


@pytest.mark.parametrize("cell", MESHES)
@pytest.mark.parametrize("order", (0, 1))
def test_probe_matrix_is_skfems_probes_on_regular_meshes(cell, order):
    mesh = MESHES[cell]()
    mesh = type(mesh).init_tensor(*[np.linspace(0, 1, 5)] * mesh.dim())
    basis = skfem.CellBasis(mesh, ELEMENTS[cell][order]())
    X = rng.uniform(0.0, 1.0, (mesh.dim(), 40))
    ours = _space(basis).probe_matrix(X).toarray()
    assert np.allclose(ours, basis.probes(X).toarray(), atol=1e-12)


@pytest.mark.parametrize("cell", MESHES)
@pytest.mark.parametrize("order", (0, 1))
def test_probe_matrix_interpolates_exactly_on_distorted_meshes(cell, order):
    # skfem's own probes fail on these hexahedra ("Newton iteration didn't converge"): it locates
    # a point through a tetrahedral split, which for a non-planar face is not the hexahedron
    mesh = MESHES[cell]()
    from vlab.geometry.mesh_check import check_mesh

    check_mesh(mesh)  # distorted, not inverted
    basis = skfem.CellBasis(mesh, ELEMENTS[cell][order]())
    X = rng.uniform(0.0, 1.0, (mesh.dim(), 40))
    X[:, :4] = mesh.p[:, :4]  # vertices: held by several elements
    P = _space(basis).probe_matrix(X)
    f = lambda x: 1.0 + 2.0 * x[0] - 0.5 * x[1] + (0.3 * x[2] if len(x) == 3 else 0.0)
    assert np.allclose(P @ f(basis.doflocs), f(X), atol=1e-12)  # the map's own fields: exact
    assert np.allclose(P.sum(axis=1), 1.0, atol=1e-13)
    if cell in ("tet", "tri") and order == 1:  # affine P2: quadratics exact too
        g = lambda x: x[0] * x[1] + x[-1] ** 2
        assert np.allclose(P @ g(basis.doflocs), g(X), atol=1e-12)


@pytest.mark.parametrize("cell", MESHES)
def test_locate_finds_the_holding_element(cell):
    mesh = MESHES[cell]()
    basis = skfem.CellBasis(mesh, ELEMENTS[cell][0]())
    X = rng.uniform(0, 1, (mesh.dim(), 60))
    cells, xi = locate(basis, X)
    assert np.allclose(basis.mapping.F(xi[:, :, None], cells)[:, :, 0], X, atol=1e-12)
    lo = -1e-12
    assert np.all(xi >= lo)
    assert np.all((xi.sum(axis=0) if cell in ("tet", "tri") else xi.max(axis=0)) <= 1 - lo)


def test_boundary_round_off_is_read_and_outside_is_an_error():
    mesh = skfem.MeshHex.init_tensor(*[np.linspace(0, 1, 4)] * 3)
    basis = skfem.CellBasis(mesh, skfem.ElementHex1())
    X = np.array([[1.0 + 1e-12, 0.5, 0.5], [0.3, -1e-13, 0.7]]).T  # off the faces by round-off
    cells, xi = locate(basis, X)
    assert np.allclose(basis.mapping.F(xi[:, :, None], cells)[:, :, 0], X, atol=1e-15)
    with pytest.raises(ValueError, match=r"point \[1.01, 0.5, 0.5\] lies outside the mesh"):
        locate(basis, np.array([[1.01, 0.5, 0.5]]).T)
    with pytest.raises(ValueError, match="outside the mesh"):
        locate(basis, np.array([[0.5, 0.5, 5.0]]).T)
