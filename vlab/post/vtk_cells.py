"""The FE space as VTK cells: quadratic cells with their mid-nodes for an order-2 space.

An order-2 space's nodes are its DOF locations (vertices first, then edge, face and cell nodes,
scikit-fem's numbering); its elements become the matching quadratic VTK cells, in VTK node order
as scikit-fem's own meshio writer orders them (``skfem.io.meshio``: the hexahedron's nodes go
through its ``HEX_MAPPING``; P2 tetrahedra, P2 triangles and Q2 quadrilaterals are already in
VTK order):

    space            VTK cell (meshio name)   nodes per cell
    P1 / Q1          tetra, hexahedron, triangle, quad        4, 8, 3, 4
    P2 tetrahedron   tetra10                 10 (4 vertices + 6 edge midpoints)
    Q2 hexahedron    hexahedron27            27 (8 + 12 edges + 6 face centres + 1 centre)
    P2 triangle      triangle6               6
    Q2 quadrilateral quad9                   9

so ParaView draws the curved cells and interpolates the displacement quadratically.

Tetrahedra are written positively oriented, as VTK expects ((x₁ − x₀) × (x₂ − x₀) · (x₃ − x₀) > 0):
vlab's split hexahedra come in both windings, and VTK's cell volume and quality filters (pyvista's
``compute_cell_sizes``) read a negative volume for half of them. Where the determinant is
negative, vertices 1 and 2 swap, and for tetra10 with them the mid-nodes of edges 01 ↔ 02 and
13 ↔ 23 (VTK's edge order 01, 12, 02, 03, 13, 23, which is scikit-fem's).
"""

from __future__ import annotations

import numpy as np
import skfem

_QUADRATIC = {skfem.ElementTetP2: "tetra10", skfem.ElementHex2: "hexahedron27",
              skfem.ElementTriP2: "triangle6", skfem.ElementQuad2: "quad9"}
_LINEAR = {skfem.MeshTet: "tetra", skfem.MeshHex: "hexahedron", skfem.MeshTri: "triangle",
           skfem.MeshQuad: "quad"}


# VTK's hexahedron corners (x, y, z) in its node order, and scikit-fem's local node of each: the
# first 8 entries of skfem.io.meshio.HEX_MAPPING (tests/test_vtk_cells_order.py), found here
# from MeshHex's reference nodes so that order-1 output does not import meshio (≈ 0.05 s)
_VTK_HEX_CORNERS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                             [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]])
_SKFEM_HEX = skfem.MeshHex().p[:, skfem.MeshHex().t[:, 0]].T
HEX_CORNERS = np.array([int(np.flatnonzero(np.all(_SKFEM_HEX == c, axis=1))[0]) for c in _VTK_HEX_CORNERS])

_TET_SWAP = {"tetra": [0, 2, 1, 3], "tetra10": [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]}


def positively_oriented(points: np.ndarray, cell: str, conn: np.ndarray) -> np.ndarray:
    """``conn`` with every tetrahedron of negative signed volume re-wound (other cells unchanged)."""
    if cell not in _TET_SWAP:
        return conn
    x = points[conn[:, :4]]
    det = np.einsum("ij,ij->i", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), x[:, 3] - x[:, 0])
    out = conn.copy()
    out[det < 0] = conn[det < 0][:, _TET_SWAP[cell]]
    return out


def vtk_cells(space) -> tuple[np.ndarray, str, np.ndarray]:
    """(points (n_nodes, 3) mm, meshio cell type, connectivity (n_cells, nodes per cell)) of
    ``space`` (a DisplacementSpace): every scalar DOF a VTK point, in the space's node order."""
    points = np.asarray(space.node_coordinates, float)
    points = np.hstack([points, np.zeros((len(points), 3 - points.shape[1]))])
    element = type(space.basis.elem)
    dofs = np.asarray(space.element_nodes)  # (n_cells, n_local), scikit-fem local order
    if element in _QUADRATIC:
        cell = _QUADRATIC[element]
        if cell == "hexahedron27":
            import skfem.io.meshio as skfem_meshio  # its 27-node order: mid-edges, faces, centre

            order = skfem_meshio.HEX_MAPPING
        else:
            order = np.arange(dofs.shape[1])
        return points, cell, positively_oriented(points, cell, dofs[:, order])
    mesh = space.basis.mesh
    cell = next(name for kind, name in _LINEAR.items() if isinstance(mesh, kind))
    order = HEX_CORNERS if cell == "hexahedron" else np.arange(dofs.shape[1])
    return points, cell, positively_oriented(points, cell, dofs[:, order])
