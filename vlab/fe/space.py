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
from functools import cached_property

import numpy as np
import skfem

from vlab.fe.blas import single_threaded_blas
from vlab.geometry.locate import locate

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

    @cached_property
    def element_dofs(self) -> np.ndarray:
        """(n_elements, dim n_local) global vector DOFs ordered (node a, component i), read-only
        (computed once: every numpy internal-force scatter reads it; 0.3 ms each on the dogbone)."""
        d = self.dim
        dofs = (d * self.element_nodes[:, :, None] + np.arange(d)).reshape(len(self.element_nodes), -1)
        dofs.flags.writeable = False
        return dofs

    def deformation_gradient(self, u: np.ndarray) -> np.ndarray:
        """F = I + ∂u/∂X at every quadrature point, shape (dim, dim, n_elements, n_qp), unitless.

        With a reference map, ∂u_i/∂X_J = Σ_m (Σ_a u_ai dN̂_qam) ∂ξ_m/∂X_J: the inner sum is one
        dense product (3 n_elements × n_local) @ (n_local × 3 n_qp) shared by all elements, the
        outer one 27 element-wise products (2–3× faster than contracting the physical dN)."""
        ue = u.reshape(-1, self.dim)[self.element_nodes]  # (e, a, i)
        if self.reference_dN is None:
            grad = np.einsum("eai,eqaJ->iJeq", ue, self.dN, optimize=True)
        else:
            n_el, n_qp = self.dx.shape
            ui = np.ascontiguousarray(ue.transpose(2, 0, 1)).reshape(3 * n_el, -1)
            with single_threaded_blas():
                G = (ui @ self._reference_dN_am).reshape(3, n_el, n_qp, 3)      # ∂u_i/∂ξ_m
            G = np.ascontiguousarray(G.transpose(0, 3, 1, 2))                    # (i, m, e, q)
            R = self.inverse_jacobian
            grad = np.empty((3, 3, n_el, n_qp))
            for i in range(3):
                for J in range(3):
                    g = np.multiply(G[i, 0], R[0, J], out=grad[i, J])
                    g += G[i, 1] * R[1, J]
                    g += G[i, 2] * R[2, J]
        for i in range(self.dim):
            grad[i, i] += 1.0
        return grad

    def element_forces(self, P: np.ndarray) -> np.ndarray:
        """Σ_q P_iJ dN_a,J dx per element, shape (n_elements, n_local, d), N. P is (d,d,e,q).

        With a reference map: Σ_(q,m) H_im dN̂_qam with H_im = Σ_J P_iJ (∂ξ_m/∂X_J dx), one dense
        product (3 n_elements × 3 n_qp) @ (3 n_qp × n_local)."""
        if self.reference_dN is None:
            return np.einsum("iJeq,eqaJ,eq->eai", P, self.dN, self.dx, optimize=True)
        n_el, n_qp = self.dx.shape
        Rw = self._inverse_jacobian_dx
        H = np.empty((3, n_el, n_qp, 3))                                         # (i, e, q, m)
        for i in range(3):
            for m in range(3):
                H[i, :, :, m] = P[i, 0] * Rw[m, 0] + P[i, 1] * Rw[m, 1] + P[i, 2] * Rw[m, 2]
        with single_threaded_blas():
            f = (H.reshape(3 * n_el, 3 * n_qp) @ self._reference_dN_qma).reshape(3, n_el, -1)
        return f.transpose(1, 2, 0)

    def workspace(self, name: str, shape: tuple[int, ...]) -> np.ndarray:
        """A persistent scratch array (uninitialised) for a kernel's large temporary.

        Fresh 10–20 MB temporaries come from the kernel as new zeroed pages every call; the
        element GEMM ran 3× slower in a Newton run than in a loop for that reason (measured on
        the 21k-DOF dogbone, 21 vs 6.5 ms). Callers use the array before their next call."""
        buffers = self.__dict__.setdefault("_workspace", {})
        if name not in buffers or buffers[name].shape != shape:
            buffers[name] = np.empty(shape)
        return buffers[name]

    @cached_property
    def _reference_dN_am(self) -> np.ndarray:
        """dN̂ as (n_local, (q, m)), C-contiguous."""
        q, a, m = self.reference_dN.shape
        return np.ascontiguousarray(self.reference_dN.transpose(1, 0, 2).reshape(a, q * m))

    @cached_property
    def _reference_dN_qma(self) -> np.ndarray:
        """dN̂ as ((q, m), n_local), C-contiguous."""
        q, a, m = self.reference_dN.shape
        return np.ascontiguousarray(self.reference_dN.transpose(0, 2, 1).reshape(q * m, a))

    @cached_property
    def inverse_jacobian_qe(self) -> np.ndarray:
        """∂ξ_m/∂X_J as (m, J, q, e), C-contiguous (element index last for the tangent kernels)."""
        return np.ascontiguousarray(np.swapaxes(self.inverse_jacobian, 2, 3))

    @cached_property
    def dx_qe(self) -> np.ndarray:
        """dx as (q, e), C-contiguous, mm³."""
        return np.ascontiguousarray(self.dx.T)

    @cached_property
    def reference_products(self) -> np.ndarray:
        """dN̂_qam dN̂_qbn as ((a, b), (q, m, n)), C-contiguous: the shared factor of every
        element stiffness on the reference cell."""
        G = self.reference_dN
        n_qp, n_loc, _ = G.shape
        return np.einsum("qam,qbn->abqmn", G, G).reshape(n_loc * n_loc, 9 * n_qp)

    @cached_property
    def reference_products_upper(self) -> np.ndarray:
        """The rows (a, b) with a ≤ b of ``reference_products``, C-contiguous."""
        n_loc = self.reference_dN.shape[1]
        a, b = np.triu_indices(n_loc)
        return np.ascontiguousarray(self.reference_products[a * n_loc + b])

    @cached_property
    def _inverse_jacobian_dx(self) -> np.ndarray:
        """∂ξ_m/∂X_J · dx, (m, J, e, q), mm²."""
        return self.inverse_jacobian * self.dx

    def probe_matrix(self, points: np.ndarray):
        """Sparse (n_points, n_nodes) interpolation matrix N_a(ξ(X)) at reference points X
        (dim, n_points), located by :func:`vlab.geometry.locate.locate` (a point on the boundary
        that misses its element by round-off is read where it is). A point outside the mesh
        raises ValueError naming it."""
        from scipy.sparse import coo_matrix

        cells, xi = locate(self.basis, points)
        basis = self.basis
        values = np.array([basis.elem.gbasis(basis.mapping, xi[:, :, None], a, tind=cells)[0][:, 0]
                           for a in range(basis.Nbfun)])  # (n_local, n_points)
        rows = np.broadcast_to(np.arange(len(cells)), values.shape)
        cols = basis.element_dofs[:, cells]  # (n_local, n_points)
        return coo_matrix((values.ravel(), (rows.ravel(), cols.ravel())),
                          shape=(len(cells), basis.N)).tocsr()


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
    # one element type and one mapping for the whole mesh: a spread sample of elements decides
    sample = np.unique(np.linspace(0, dN.shape[0] - 1, min(dN.shape[0], 256)).astype(int))
    rebuilt = np.einsum("qam,mJeq->eqaJ", reference_dN, inverse_jacobian[:, :, sample])
    if rebuilt.shape != dN[sample].shape or not np.allclose(rebuilt, dN[sample], rtol=1e-12,
                                                            atol=1e-12 * np.abs(dN).max()):
        return None, None
    return reference_dN, np.ascontiguousarray(inverse_jacobian)

