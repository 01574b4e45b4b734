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
"""

from __future__ import annotations

import numpy as np
import skfem
import skfem.io.meshio as skfem_meshio

_QUADRATIC = {skfem.ElementTetP2: "tetra10", skfem.ElementHex2: "hexahedron27",
              skfem.ElementTriP2: "triangle6", skfem.ElementQuad2: "quad9"}
_LINEAR = {skfem.MeshTet: "tetra", skfem.MeshHex: "hexahedron", skfem.MeshTri: "triangle",
           skfem.MeshQuad: "quad"}


def vtk_cells(space) -> tuple[np.ndarray, str, np.ndarray]:
    """(points (n_nodes, 3) mm, meshio cell type, connectivity (n_cells, nodes per cell)) of
    ``space`` (a DisplacementSpace): every scalar DOF a VTK point, in the space's node order."""
    points = np.asarray(space.node_coordinates, float)
    points = np.hstack([points, np.zeros((len(points), 3 - points.shape[1]))])
    element = type(space.basis.elem)
    dofs = np.asarray(space.element_nodes)  # (n_cells, n_local), scikit-fem local order
    if element in _QUADRATIC:
        cell = _QUADRATIC[element]
        order = skfem_meshio.HEX_MAPPING if cell == "hexahedron27" else np.arange(dofs.shape[1])
        return points, cell, dofs[:, order]
    mesh = space.basis.mesh
    cell = next(name for kind, name in _LINEAR.items() if isinstance(mesh, kind))
    order = skfem_meshio.HEX_MAPPING[:8] if cell == "hexahedron" else np.arange(dofs.shape[1])
    return points, cell, dofs[:, order]
