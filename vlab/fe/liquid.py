"""A body whose face closes a liquid-filled chamber: the bulge tester's hydraulics
(vlab.loading.bulge). Same interface as every body (vlab.fe.body), plus ``set_load(t)``, which the
load stepping calls before each substep (the pumped volume or the pressure depends on t).

The wetted face is triangulated (each quadrilateral facet into two triangles, counter-clockwise
seen from +z, the side the liquid pushes towards), and the volume it encloses with the plane
z = 0 is the sum of the prisms under its triangles, exact for the facetted face as long as its
edge stays on z = 0 or on vertical symmetry planes (a clamped rim, the planes x = 0, y = 0):

    V(u) = Σ_T z̄_T A_T,   z̄ = (z₁ + z₂ + z₃) / 3,   A = ½ Σ_a (x_a y_{a+1} − x_{a+1} y_a)   (mm³)
    ∂V/∂z_a = A / 3,  ∂V/∂x_a = z̄ (y_{a+1} − y_{a−1}) / 2,  ∂V/∂y_a = z̄ (x_{a−1} − x_{a+1}) / 2,
    ∂²V/∂x_a∂z_b = (y_{a+1} − y_{a−1}) / 6,  ∂²V/∂y_a∂z_b = (x_{a−1} − x_{a+1}) / 6,
    ∂²V/∂x_a∂y_b = z̄ (δ_{b,a+1} − δ_{b,a−1}) / 2   (a, b = 1..3 cyclic; the other blocks 0).

Σ_a ∂V/∂z_a over the face is its projected area, so the clamped rim's z reaction is −p times
it, as equilibrium of the whole sheet demands.

Two controls of the liquid:

- ``"volume"``: a syringe pumps the volume V_p(t) = t V_p(1) into a chamber of liquid volume V₀ and
  bulk modulus K_f; the liquid's pressure is p = K_f (V_p − V) / V₀ (MPa) and its energy
  ½ (K_f / V₀) (V_p − V)². The total potential Π = W(u) + ½ k (V_p(t) − V(u))², k = K_f / V₀, has
  f = f_int − p ∂V/∂u and K = K_int + k (∂V/∂u)(∂V/∂u)ᵀ − p ∂²V/∂u². With k far above the sheet's
  own stiffness against volume, V follows V_p (to p V₀ / K_f) and the sheet passes a pressure
  maximum: the liquid's stiffness keeps K positive definite where the sheet's alone is not.
- ``"pressure"``: a pressure p(t) = t p* (a gas reservoir, no stiffness): Π = W(u) − p V(u),
  f = f_int − p ∂V/∂u, K = K_int − p ∂²V/∂u². Past a pressure maximum there is no equilibrium.

The rank-one term couples every wetted DOF with every other: the tangent's pattern is the inner
body's with the wetted DOFs' clique added (a few hundred DOFs on a quarter membrane).
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import scipy.sparse as sp

from vlab.fe.body import LoadWrapper
from vlab.fe.problem import Evaluation
from vlab.loading.liquid import Liquid

__all__ = ["Liquid", "LiquidBody", "enclosed_volume", "enclosed_volume_gradient"]


def _prisms(corners: np.ndarray):
    """(V, ∂V/∂x per corner (T, 3, 3), ∂²V per triangle (T, 3, 3, 3, 3) [a, i, b, j]) of the
    triangles' corners (T, 3 corners, 3 components) (module docstring)."""
    x, y, z = corners[..., 0], corners[..., 1], corners[..., 2]
    nxt, prv = [1, 2, 0], [2, 0, 1]
    area = 0.5 * np.sum(x * y[:, nxt] - x[:, nxt] * y, axis=1)
    zbar = z.mean(axis=1)
    dA = np.stack([0.5 * (y[:, nxt] - y[:, prv]), 0.5 * (x[:, prv] - x[:, nxt])], axis=-1)  # (T, a, {x, y})
    grad = np.empty_like(corners)
    grad[..., :2] = zbar[:, None, None] * dA
    grad[..., 2] = area[:, None] / 3.0
    H = np.zeros(corners.shape[:1] + (3, 3, 3, 3))
    for i in (0, 1):  # ∂²V/∂(x or y)_a ∂z_b = ∂A/∂(x or y)_a / 3, for every b
        H[:, :, i, :, 2] = dA[:, :, None, i] / 3.0
        H[:, :, 2, :, i] = dA[:, None, :, i] / 3.0
    for a in range(3):  # ∂²V/∂x_a ∂y_b = z̄ (δ_{b,a+1} − δ_{b,a−1}) / 2 and its transpose
        H[:, a, 0, nxt[a], 1] += 0.5 * zbar
        H[:, a, 0, prv[a], 1] -= 0.5 * zbar
        H[:, nxt[a], 1, a, 0] += 0.5 * zbar
        H[:, prv[a], 1, a, 0] -= 0.5 * zbar
    return float(np.sum(zbar * area)), grad, H


def enclosed_volume(x: np.ndarray, triangles: np.ndarray) -> float:
    """V (mm³) of the node positions ``x`` (n, 3) under ``triangles`` (module docstring)."""
    return _prisms(x[triangles])[0]


def enclosed_volume_gradient(x: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the wetted nodes (m,), ∂V/∂x at them (m, 3), mm²) of the node positions ``x`` (n, 3)."""
    nodes = np.unique(triangles)
    _, grad_t, _ = _prisms(x[triangles])
    return nodes, _per_node(grad_t, np.searchsorted(nodes, triangles), len(nodes))


def _per_node(grad_t: np.ndarray, local: np.ndarray, m: int) -> np.ndarray:
    """The triangles' corner gradients (T, 3, 3) summed onto their m nodes (m, 3)."""
    grad = np.zeros((m, 3))
    for k in range(3):
        np.add.at(grad, local[:, k], grad_t[:, k])
    return grad


class LiquidBody(LoadWrapper):
    """``body`` with a liquid under ``liquid.triangles`` (module docstring); ``set_load(t)``."""

    pattern = None  # the inner pattern with the wetted clique, set in __init__

    def __init__(self, body, liquid: Liquid):
        self.inner, self.liquid, self.t = body, liquid, 0.0
        tri = np.asarray(liquid.triangles, dtype=np.int64)
        self._X = body.space.node_coordinates
        self._nodes = np.unique(tri)  # the wetted nodes
        self._local = np.searchsorted(self._nodes, tri)  # the triangles' corners among the wetted nodes
        self._dofs = (3 * self._nodes[:, None] + np.arange(3)).ravel()  # the clique's DOFs, node-major
        inner = body.pattern
        n = inner.n
        Ki = sp.csr_matrix((np.ones(len(inner.indices)), inner.indices, inner.indptr), shape=(n, n))
        m = len(self._dofs)
        clique = sp.csr_matrix((np.ones(m * m), (np.repeat(self._dofs, m), np.tile(self._dofs, m))), shape=(n, n))
        union = (Ki + clique).tocsr()
        union.sort_indices()
        self.pattern = SimpleNamespace(n=n, indptr=union.indptr, indices=union.indices)
        keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(union.indptr)) * n + union.indices
        inner_rows = np.repeat(np.arange(n, dtype=np.int64), np.diff(inner.indptr))
        self._inner_slots = np.searchsorted(keys, inner_rows * n + inner.indices)
        self._clique_slots = np.searchsorted(keys, (self._dofs[:, None] * n + self._dofs[None, :]).ravel())
        self._nnz = len(keys)

    def set_load(self, t: float) -> None:
        """The load parameter of the evaluations from now on (the stepper's substep target)."""
        self.t = float(t)

    def load_rate(self, evaluation: Evaluation) -> np.ndarray:
        """∂f/∂t at fixed u (N): −(dp/dt) ∂V/∂u, dp/dt = k V_p(1) (volume) or p* (pressure)."""
        _, _, grad, _ = self.state(evaluation.u)
        rate = self.liquid.target * (self.liquid.stiffness if self.liquid.control == "volume" else 1.0)
        out = np.zeros(len(evaluation.u))
        out[self._dofs] = -rate * grad.ravel()
        return out

    def state(self, u: np.ndarray) -> tuple[float, float, np.ndarray, np.ndarray]:
        """(V, p, ∂V/∂x per wetted node (m, 3), ∂²V per triangle) at ``u``."""
        x = self._X[self._nodes] + u[self._dofs].reshape(-1, 3)
        volume, grad_t, hess_t = _prisms(x[self._local])
        grad = _per_node(grad_t, self._local, len(x))
        return volume, self.liquid.pressure(self.t, volume), grad, hess_t

    def _loaded(self, ev: Evaluation, u: np.ndarray) -> Evaluation:
        if not ev.admissible:
            return ev
        volume, p, grad, _ = self.state(u)
        f = ev.f_int.copy()
        f[self._dofs] -= p * grad.ravel()
        if self.liquid.control == "pressure":
            W = ev.W - p * volume
        else:
            W = ev.W + 0.5 * p * p / self.liquid.stiffness
        return replace(ev, W=W, f_int=f)

    def stiffness(self, evaluation: Evaluation) -> sp.csr_matrix:
        K = self.inner.stiffness(evaluation)
        data = np.zeros(self._nnz)
        if len(K.data) == len(self._inner_slots):  # on the inner pattern, as every body assembles
            data[self._inner_slots] = K.data
        else:
            coo = K.tocoo()
            n = self.pattern.n
            keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(self.pattern.indptr)) * n + self.pattern.indices
            np.add.at(data, np.searchsorted(keys, coo.row.astype(np.int64) * n + coo.col), coo.data)
        _, p, grad, hess = self.state(evaluation.u)
        m3 = 3 * len(self._nodes)
        dofs = (3 * self._local[:, :, None] + np.arange(3)).reshape(len(self._local), 9)  # local DOFs per triangle
        flat = (dofs[:, :, None] * m3 + dofs[:, None, :]).ravel()
        dense = -p * np.bincount(flat, weights=hess.reshape(len(hess), 81).ravel(), minlength=m3 * m3)
        if self.liquid.control == "volume":
            g = grad.ravel()
            dense += self.liquid.stiffness * np.outer(g, g).ravel()
        data[self._clique_slots] += dense
        return sp.csr_matrix((data, self.pattern.indices, self.pattern.indptr), shape=(self.pattern.n,) * 2)
