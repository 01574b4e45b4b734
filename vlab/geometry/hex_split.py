"""Conforming tetrahedra from a swept hexahedral mesh whose blocks are numbered in different
lattice orders (the cylinder's O-grid), where the Kuhn split of each block (vlab.geometry.lattice)
does not match across block faces.

Each hexahedron of a mesh swept along x (four nodes at one x, four at the next, paired along x)
is cut into two triangular prisms by the diagonal plane through the vertex of its section quad
with the smallest section index (the same for every layer of a column, so the x-faces match
between layers), and each prism into three tetrahedra by the smallest-global-index rule
(Dompierre, Labbé, Vallet & Camarero, "How to subdivide pyramids, prisms and hexahedra into
tetrahedra", 8th International Meshing Roundtable, 1999): every quadrilateral face is split by
its diagonal through its smallest vertex index, which depends on the face alone, so two elements
sharing a face split it alike. With the prism's smallest vertex a (bottom a, b, c under a', b', c'),
the tetrahedra are (a, b', c', a') and the pyramid (a; b, c, c', b') split by the diagonal of
b c c' b' through its smallest vertex. Six tetrahedra per hexahedron, no new node; the P2 nodes
are the Q2 nodes (one midpoint per hexahedron edge, face and the cut plane's diagonal).
"""

from __future__ import annotations

import numpy as np
import skfem

__all__ = ["swept_hex_to_tets"]


def _prism_tets(bottom: np.ndarray, top: np.ndarray) -> list[tuple[int, ...]]:
    """Three tetrahedra (global node indices) of the prism bottom (a, b, c), top (a', b', c')."""
    nodes = np.concatenate([bottom, top])
    k = int(np.argmin(nodes))
    if k >= 3:  # the smallest on top: the same rule with the prism upside down
        bottom, top, k = top, bottom, k - 3
    a, b, c = np.roll(bottom, -k)
    a2, b2, c2 = np.roll(top, -k)
    if min(b, c2) < min(c, b2):  # the face b c c' b' split by b–c'
        pyramid = [(a, b, c, c2), (a, b, c2, b2)]
    else:  # by c–b'
        pyramid = [(a, b, c, b2), (a, c, c2, b2)]
    return [(a, b2, c2, a2)] + pyramid


def swept_hex_to_tets(mesh: skfem.MeshHex) -> skfem.MeshTet:
    """The MeshTet of the module docstring (same nodes)."""
    p = mesh.p
    section = np.unique(np.round(p[1:].T, 12), axis=0, return_inverse=True)[1].ravel()  # column id per node
    tets = []
    for hexa in mesh.t.T:
        order = np.argsort(p[0, hexa], kind="stable")
        low, high = hexa[order[:4]], hexa[order[4:]]
        c = p[1:, low].mean(axis=1)
        low = low[np.argsort(np.arctan2(p[2, low] - c[1], p[1, low] - c[0]))]  # cyclic around the quad
        high = np.array([high[np.flatnonzero(section[high] == section[n])[0]] for n in low])
        m = int(np.argmin(section[low]))
        low, high = np.roll(low, -m), np.roll(high, -m)
        for tri in ((0, 1, 2), (0, 2, 3)):
            tets += _prism_tets(low[list(tri)], high[list(tri)])
    t = np.array(tets, dtype=np.int64).T
    X = p[:, t]  # (3, 4, n)
    volume = np.einsum("in,in->n", np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0], axis=0), X[:, 3] - X[:, 0])
    flip = volume < 0
    t[1, flip], t[2, flip] = t[2, flip].copy(), t[1, flip].copy()
    return skfem.MeshTet(np.ascontiguousarray(p), np.ascontiguousarray(t))
