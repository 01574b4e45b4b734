"""The arithmetic of the size budget (vlab/geometry/budget.py): what a shape's ``count`` (its entry in
vlab/geometry/shapes.py) returns, and the counting rules the structured shapes share.

No array is allocated: every count is arithmetic on the dimensions, in Python ints (a huge count
stays exact instead of overflowing). Structured hexahedra over n_i divisions: elements E = Π n_i,
vertices Π(n_i + 1); order 2 (Q2, and P2 on the Kuhn split, which adds the same face and body
diagonals' midpoints) Π(2 n_i + 1) nodes; tetrahedra 6E (Kuhn split), triangles 2E.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["MeshCount", "CUT", "div", "structured", "lattice_count"]

CUT = {"none": 0, "half": 1, "quarter": 2, "eighth": 3}  # mesh.symmetry: planes cut (x, y, z in turn)


@dataclass(frozen=True)
class MeshCount:
    """A shape's mesh counted before it is built: elements, nodes, space dimension (3, or 2 for a
    sheet) and which rule counted (for the budget's message)."""

    elements: int
    nodes: int
    dim: int
    how: str


def div(length: float, size: float) -> int:
    """lattice.divisions without numpy (and without overflow: a huge count stays a Python int)."""
    return max(1, math.ceil(length / size - 1e-9))


def structured(n: tuple[int, ...], cell: str, order: int) -> tuple[int, int]:
    """(elements, nodes) of a structured mesh of n_i divisions per axis (module docstring)."""
    elements = math.prod(n) * (6 if cell == "tet" else 2 if cell == "tri" else 1)
    nodes = math.prod((2 if order == 2 else 1) * k + 1 for k in n)
    return elements, nodes


def lattice_count(n: tuple[int, ...], mesh, how: str) -> MeshCount:
    """The count of a structured mesh of n_i divisions in the scene's cell and order."""
    return MeshCount(*structured(n, mesh.cell, mesh.order), dim=len(n), how=how)
