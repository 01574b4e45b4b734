"""The discrete displacement space: scikit-fem supplies the mesh, element, quadrature and
shape-function gradients; vlab owns the vector DOF layout and the hot path.

Vector DOF numbering: ``dof = dim * node + component``, where ``node`` is a scalar DOF of the
scikit-fem basis (mesh vertices first, then edge/face/interior nodes for order 2) and ``dim`` the
mesh dimension (3 for solids, 2 for sheets). The nodal displacement array ``u`` therefore
reshapes to ``(n_nodes, dim)``.

2D (triangles, quadrilaterals) is a sheet of thickness t in the (x, y) plane: the integration
measure dx = quadrature weight × det(reference map) × t is the reference VOLUME a quadrature point
stands for, so energies (mJ), forces (N) and stiffnesses (N/mm) keep their 3D units and the 2D
material law (vlab.materials.plane) works per unit volume like the 3D ones.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import skfem

# Quadrature order per (cell, element order). P1 tets have constant F, so one point is exact;
# the others use the lowest Gauss rule that integrates the linearised stiffness exactly.
_ELEMENTS = {
    ("tet", 1): (skfem.ElementTetP1, 1),
    ("tet", 2): (skfem.ElementTetP2, 2),
    ("hex", 1): (skfem.ElementHex1, 3),
    ("hex", 2): (skfem.ElementHex2, 5),
    ("tri", 1): (skfem.ElementTriP1, 1),
    ("tri", 2): (skfem.ElementTriP2, 2),
    ("quad", 1): (skfem.ElementQuad1, 3),
    ("quad", 2): (skfem.ElementQuad2, 5),
}
_CELLS = {skfem.MeshHex: "hex", skfem.MeshTet: "tet", skfem.MeshQuad: "quad", skfem.MeshTri: "tri"}


@dataclass(frozen=True)
class DisplacementSpace:
    """Vector Lagrange space on a 3D (or 2D sheet) mesh, flattened for vectorized kernels.

    Attributes
    ----------
    basis : the scalar scikit-fem basis (geometry, doflocs, probes).
    element_nodes : (n_elements, n_local) scalar DOF of each local node.
    dN : (n_elements, n_qp, n_local, dim) shape-function gradients dN_a/dX_J, 1/mm.
    dx : (n_elements, n_qp) quadrature weight times det of the reference map (times the sheet
        thickness in 2D), mm³.
    reference_dN : (n_qp, n_local, 3) gradients dN̂_a/dξ_m on the reference cell, the same for
        every element, or None if the element is not isoparametric in the checked sense.
    inverse_jacobian : (3, 3, n_elements, n_qp) ∂ξ_m/∂X_J, so that
        dN_a/dX_J = Σ_m dN̂_a/dξ_m ∂ξ_m/∂X_J (verified at build time), 1/mm. 3D only (the
        2D kernels take the generic path).
    dim : 3, or 2 for a sheet.
    """

    basis: skfem.CellBasis
    element_nodes: np.ndarray
    dN: np.ndarray
    dx: np.ndarray
    reference_dN: np.ndarray | None = None
    inverse_jacobian: np.ndarray | None = None
    dim: int = 3

    @classmethod
    def build(cls, mesh: skfem.Mesh, order: int, thickness: float = 1.0) -> "DisplacementSpace":
        """The space of ``order`` on ``mesh``; ``thickness`` (mm) of a 2D sheet scales dx."""
        cell = next(name for kind, name in _CELLS.items() if isinstance(mesh, kind))
        element_type, intorder = _ELEMENTS[(cell, order)]
        basis = skfem.Basis(mesh, element_type(), intorder=intorder)
        grads = np.stack([phi[0].grad for phi in basis.basis])  # (a, J, e, q)
        dN = np.ascontiguousarray(grads.transpose(2, 3, 0, 1))
        dim = mesh.dim()
        if dim == 2:
            return cls(basis, np.ascontiguousarray(basis.element_dofs.T), dN,
                       thickness * np.asarray(basis.dx), dim=2)
        reference_dN, inverse_jacobian = _reference_map(basis, dN)
        return cls(basis, np.ascontiguousarray(basis.element_dofs.T), dN, np.asarray(basis.dx),
                   reference_dN, inverse_jacobian)

    @property
    def n_nodes(self) -> int:
        return self.basis.N

    @property
    def n_dofs(self) -> int:
        return self.dim * self.basis.N

    @property
    def node_coordinates(self) -> np.ndarray:
        """(n_nodes, dim) reference coordinates of every scalar DOF, mm."""
        return self.basis.doflocs.T

    @property
    def element_dofs(self) -> np.ndarray:
        """(n_elements, dim n_local) global vector DOFs ordered (node a, component i)."""
        d = self.dim
        return (d * self.element_nodes[:, :, None] + np.arange(d)).reshape(len(self.element_nodes), -1)

    def deformation_gradient(self, u: np.ndarray) -> np.ndarray:
        """F = I + ∂u/∂X at every quadrature point, shape (dim, dim, n_elements, n_qp), unitless."""
        ue = u.reshape(-1, self.dim)[self.element_nodes]  # (e, a, i)
        grad = np.einsum("eai,eqaJ->iJeq", ue, self.dN, optimize=True)
        for i in range(self.dim):
            grad[i, i] += 1.0
        return grad

    def probe_matrix(self, points: np.ndarray):
        """Sparse (n_points, n_nodes) interpolation matrix at reference points (dim, n_points)."""
        return self.basis.probes(np.asarray(points, dtype=float)).tocsr()


def _reference_map(basis: skfem.CellBasis, dN: np.ndarray):
    """(dN̂ (q,a,m), ∂ξ/∂X (m,J,e,q)) if they reproduce the basis gradients, else (None, None).

    The stiffness kernel pulls the material tangent back to the reference cell, where the
    shape-function gradients are shared by all elements, so its contraction is one dense matrix
    product over all elements instead of many tiny ones.
    """
    try:
        inverse_jacobian = np.asarray(basis.mapping.invDF(basis.X))
        reference = np.stack([basis.elem.lbasis(basis.X, a)[1] for a in range(basis.Nbfun)])
    except (AttributeError, NotImplementedError, TypeError, ValueError):
        return None, None
    reference_dN = np.ascontiguousarray(reference.transpose(2, 0, 1))  # (q, a, m)
    rebuilt = np.einsum("qam,mJeq->eqaJ", reference_dN, inverse_jacobian)
    if rebuilt.shape != dN.shape or not np.allclose(rebuilt, dN, rtol=1e-12,
                                                    atol=1e-12 * np.abs(dN).max()):
        return None, None
    return reference_dN, np.ascontiguousarray(inverse_jacobian)
