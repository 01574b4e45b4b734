"""The discrete displacement space: scikit-fem supplies the mesh, element, quadrature and
shape-function gradients; vlab owns the vector DOF layout and the hot path.

Vector DOF numbering: ``dof = 3 * node + component``, where ``node`` is a scalar DOF of the
scikit-fem basis (mesh vertices first, then edge/face/interior nodes for order 2). The nodal
displacement array ``u`` therefore reshapes to ``(n_nodes, 3)``.
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
}


@dataclass(frozen=True)
class DisplacementSpace:
    """Vector Lagrange space on a 3D mesh, flattened for vectorized kernels.

    Attributes
    ----------
    basis : the scalar scikit-fem basis (geometry, doflocs, probes).
    element_nodes : (n_elements, n_local) scalar DOF of each local node.
    dN : (n_elements, n_qp, n_local, 3) shape-function gradients dN_a/dX_J, 1/mm.
    dx : (n_elements, n_qp) quadrature weight times det of the reference map, mm³.
    reference_dN : (n_qp, n_local, 3) gradients dN̂_a/dξ_m on the reference cell, the same for
        every element, or None if the element is not isoparametric in the checked sense.
    inverse_jacobian : (3, 3, n_elements, n_qp) ∂ξ_m/∂X_J, so that
        dN_a/dX_J = Σ_m dN̂_a/dξ_m ∂ξ_m/∂X_J (verified at build time), 1/mm.
    """

    basis: skfem.CellBasis
    element_nodes: np.ndarray
    dN: np.ndarray
    dx: np.ndarray
    reference_dN: np.ndarray | None = None
    inverse_jacobian: np.ndarray | None = None

    @classmethod
    def build(cls, mesh: skfem.Mesh, order: int) -> "DisplacementSpace":
        cell = "hex" if isinstance(mesh, skfem.MeshHex) else "tet"
        element_type, intorder = _ELEMENTS[(cell, order)]
        basis = skfem.Basis(mesh, element_type(), intorder=intorder)
        grads = np.stack([phi[0].grad for phi in basis.basis])  # (a, J, e, q)
        dN = np.ascontiguousarray(grads.transpose(2, 3, 0, 1))
        reference_dN, inverse_jacobian = _reference_map(basis, dN)
        return cls(basis, np.ascontiguousarray(basis.element_dofs.T), dN, np.asarray(basis.dx),
                   reference_dN, inverse_jacobian)

    @property
    def n_nodes(self) -> int:
        return self.basis.N

    @property
    def n_dofs(self) -> int:
        return 3 * self.basis.N

    @property
    def node_coordinates(self) -> np.ndarray:
        """(n_nodes, 3) reference coordinates of every scalar DOF, mm."""
        return self.basis.doflocs.T

    @property
    def element_dofs(self) -> np.ndarray:
        """(n_elements, 3 n_local) global vector DOFs ordered (node a, component i)."""
        return (3 * self.element_nodes[:, :, None] + np.arange(3)).reshape(len(self.element_nodes), -1)

    def deformation_gradient(self, u: np.ndarray) -> np.ndarray:
        """F = I + ∂u/∂X at every quadrature point, shape (3, 3, n_elements, n_qp), unitless."""
        ue = u.reshape(-1, 3)[self.element_nodes]  # (e, a, i)
        grad = np.einsum("eai,eqaJ->iJeq", ue, self.dN, optimize=True)
        grad[0, 0] += 1.0
        grad[1, 1] += 1.0
        grad[2, 2] += 1.0
        return grad

    def probe_matrix(self, points: np.ndarray):
        """Sparse (n_points, n_nodes) interpolation matrix at reference points (3, n_points)."""
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
