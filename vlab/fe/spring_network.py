"""A mass–spring network on the specimen's mesh: the same lab, a discrete model instead of a continuum.

Every pair of vertices that share an element is joined by a spring (for tetrahedra these are the
mesh edges; a hexahedron's 12 edges alone would leave it free to shear, so its 12 face diagonals
and 4 body diagonals are springs too). With reference length L, current length l = |x_b − x_a|:

    ε = l / L − 1                            spring strain, 1
    ψ = ½ k̃ ε² L                             spring energy, mJ (= N·mm)
    f_b = −f_a = k̃ ε n,  n = (x_b − x_a)/l    spring force on its ends, N
    K_bb = (k̃/L) n⊗n + (k̃ ε / l)(I − n⊗n)     stiffness block, N/mm (K_aa = K_bb = −K_ab)

Choice of k̃ (N): each spring stands for a bar of modulus c·E and volume v_s, where v_s is its share
of the elements it belongs to (every element's volume split equally among its springs), so
ψ = ½ (c E) ε² v_s and k̃ = c E v_s / L. For bars pointing in all directions equally, the average
⟨n_i n_j n_k n_l⟩ = (δ_ij δ_kl + δ_ik δ_jl + δ_il δ_jk)/15 gives λ = μ = c E/15, hence
E_network = c E / 6 and ν_network = 1/4 whatever the input ν (Cauchy's relation for central forces).
So c = 6 makes the isotropic network's E equal the input E; a real tessellation is not isotropic,
and its measured E and ν are what the mesh makes them, which is what this model is here to show.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from vlab.fe.assembly import SparsityPattern
from vlab.fe.problem import Evaluation
from vlab.fe.body import BodyDefaults
from vlab.fe.space import DisplacementSpace
from vlab.fe.timers import ASSEMBLY, timed

#: c in k̃ = c E v_s / L: the isotropic-orientation average makes E_network = c E / 6.
ISOTROPIC_FACTOR = 6.0
_ORDER1_NODES = {4: "tet", 8: "hex"}


class SpringNetwork(BodyDefaults):
    """Body with the interface of :class:`vlab.fe.problem.HyperelasticBody` (order-1 meshes only)."""

    name = "spring-network"

    def __init__(self, space: DisplacementSpace, E: float):
        n_local = space.element_nodes.shape[1]
        if n_local not in _ORDER1_NODES or space.n_nodes != space.basis.mesh.nvertices:
            raise ValueError("material.model 'spring-network' needs mesh.order = 1 (springs join mesh "
                             f"vertices); got elements with {n_local} nodes")
        if not E > 0:
            raise ValueError(f"spring-network: E must be > 0 MPa, got {E}")
        self.space = space
        self.pattern = SparsityPattern.build(space.element_nodes)
        self.E = float(E)
        la, lb = np.triu_indices(n_local, k=1)  # every local vertex pair of an element
        nodes = space.element_nodes
        a, b = nodes[:, la], nodes[:, lb]  # (e, pairs)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        keys = lo.astype(np.int64) * space.n_nodes + hi
        unique, first, self._spring_of = np.unique(keys.ravel(), return_index=True, return_inverse=True)
        self._spring_of = self._spring_of.reshape(keys.shape)  # (e, pairs) -> spring index
        self.a, self.b = (unique // space.n_nodes).astype(np.int64), (unique % space.n_nodes).astype(np.int64)
        X = space.node_coordinates
        self.L = np.linalg.norm(X[self.b] - X[self.a], axis=1)
        element_volume = space.dx.sum(axis=1)
        share = np.repeat(element_volume / len(la), len(la)).reshape(keys.shape)  # mm³ per (e, pair)
        self.volume = np.bincount(self._spring_of.ravel(), weights=share.ravel(), minlength=len(unique))
        self._fraction = share / self.volume[self._spring_of]  # part of each spring owned by an element
        self.k = ISOTROPIC_FACTOR * self.E * self.volume / self.L  # k̃, N
        self._slots = self._stiffness_slots(first, la, lb, a.ravel(), b.ravel())

    @property
    def n_springs(self) -> int:
        return len(self.L)

    def _stiffness_slots(self, first, la, lb, a_flat, b_flat) -> np.ndarray:
        """CSR data slots of every spring's four 3×3 blocks, located in the element owning it.

        Element entries use the pattern's block layout (i, k, e, a, b)."""
        n_pairs = len(la)
        n_el, n_loc = self.space.element_nodes.shape
        element, pair = first // n_pairs, first % n_pairs
        local = np.stack([la[pair], lb[pair]], axis=1)  # (s, 2) local node of end a, end b
        c = np.arange(3)
        # (s, end_row, end_col, i, k) -> flat index of entry (i, k, element, node_row, node_col)
        a_node = local[:, :, None, None, None]
        b_node = local[:, None, :, None, None]
        i, k = c[None, None, None, :, None], c[None, None, None, None, :]
        flat = ((i * 3 + k) * n_el + element[:, None, None, None, None]) * n_loc**2 + a_node * n_loc + b_node
        return self.pattern.slot[flat]

    def _geometry(self, u: np.ndarray):
        x = self.space.node_coordinates + u.reshape(-1, 3)
        d = x[self.b] - x[self.a]
        length = np.linalg.norm(d, axis=1)
        return d, length

    def gradient(self, u: np.ndarray) -> np.ndarray:
        """The FE deformation gradient of the mesh (for reports), as ``evaluate`` computes it."""
        return self.space.deformation_gradient(u)

    @timed(ASSEMBLY)
    def evaluate(self, u: np.ndarray) -> Evaluation:
        """Energy, spring forces and (for reports) the FE deformation gradient of the mesh.

        A state in which any spring has collapsed to zero length is inadmissible (W = +inf)."""
        F = self.gradient(u)
        J = np.linalg.det(np.moveaxis(F, (0, 1), (-2, -1)))
        worst = np.unravel_index(int(np.argmin(J)), J.shape)
        worst = (int(worst[0]), int(worst[1]))
        d, length = self._geometry(u)
        if not np.all(length > 0.0):
            return Evaluation(u, F, np.inf, None, float(J[worst]), worst)
        eps = length / self.L - 1.0
        W = float(np.sum(0.5 * self.k * eps**2 * self.L))
        f = (self.k * eps / length)[:, None] * d  # force on end b, N
        f_int = np.zeros((self.space.n_nodes, 3))
        np.add.at(f_int, self.b, f)
        np.add.at(f_int, self.a, -f)
        return Evaluation(u, F, W, f_int.ravel(), float(J[worst]), worst)

    @timed(ASSEMBLY)
    def stiffness(self, evaluation: Evaluation) -> sp.csr_matrix:
        """K = ∂f_int/∂u, N/mm, in the same sparsity pattern as the finite-element body."""
        d, length = self._geometry(evaluation.u)
        n = d / length[:, None]
        eps = length / self.L - 1.0
        nn = n[:, :, None] * n[:, None, :]
        block = ((self.k / self.L)[:, None, None] * nn
                 + (self.k * eps / length)[:, None, None] * (np.eye(3) - nn))  # (s, 3, 3)
        signs = np.array([[1.0, -1.0], [-1.0, 1.0]])
        entries = signs[None, :, :, None, None] * block[:, None, None, :, :]
        data = np.bincount(self._slots.ravel(), weights=entries.ravel(), minlength=len(self.pattern.indices))
        return sp.csr_matrix((data, self.pattern.indices, self.pattern.indptr),
                             shape=(self.pattern.n, self.pattern.n))

    def cell_cauchy(self, evaluation: Evaluation) -> np.ndarray:
        """Virial (Cauchy) stress per element, (3, 3, n_elements), MPa:
            σ_e = 1/(J_e V_e) Σ_{s ∈ e} w_es f_s ⊗ d_s,
        w_es the part of spring s owned by element e, so that Σ_e J_e V_e σ_e = Σ_s f_s ⊗ d_s."""
        d, length = self._geometry(evaluation.u)
        eps = length / self.L - 1.0
        f = (self.k * eps / length)[:, None] * d
        virial = f[:, :, None] * d[:, None, :]  # (s, 3, 3), N·mm
        per_pair = virial[self._spring_of] * self._fraction[..., None, None]  # (e, pairs, 3, 3)
        dx = self.space.dx
        J = np.linalg.det(np.moveaxis(evaluation.F, (0, 1), (-2, -1)))
        current_volume = np.sum(J * dx, axis=1)
        return np.moveaxis(per_pair.sum(axis=1) / current_volume[:, None, None], 0, -1)
