"""The size budget: nodes, DOFs and memory of a scene's mesh estimated from its geometry, before
any mesh is built, so that a request the machine cannot hold fails at once with the numbers.

Counts (no array is allocated; every count is arithmetic on the dimensions):
- block: n_i = ceil(side_i / h) divisions per side (vlab.geometry.lattice.divisions), per half
  side and mirrored for a symmetry-reduced block, which meshes 1/2, 1/4, 1/8 of it;
- dogbone: the structured mapper's divisions: along x ceil(l_fine / h_g) + ceil(l_tabs / h) with
  l_fine = parallel length + 2 × transition, across 2 ceil(w / 2 h_g), through 2 ceil(t / 2 min(h, h_g));
- cruciform: its bounding square (2 × arm end) × thickness at min(h, h_g): an upper bound;
- sheet: n_x n_y quadrilaterals (two triangles each);
- imported mesh: its own nodes and cells (order 2 adds one node per edge, and per face and cell
  for hexahedra).
Structured hexahedra: elements E = Π n_i; vertices Π(n_i + 1); order 2 (Q2, and P2 on the Kuhn
split, which adds the same face and body diagonals' midpoints) Π(2 n_i + 1) nodes. Tetrahedra: 6E
(Kuhn split). DOFs = nodes × dimension.

Memory (bytes) ≈ BASE_BYTES + BYTES_PER_DOF[(cell, order)] × DOFs, fitted on peak RSS of
``vlab run`` on blocks of 4,000–60,000 DOFs (PARDISO, numba kernels; see the table in the README
and tests/test_budget.py): the factorization of K and the per-quadrature-point tangents dominate.

Limits: DOFs ≤ mesh.max_dofs (default DEFAULT_MAX_DOFS) and estimated memory ≤ the memory
available now (psutil), with the numbers in the message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from vlab.fields import SceneError

DEFAULT_MAX_DOFS = 2_000_000
BASE_BYTES = 450e6  # python, numpy/scipy, numba, VTK loaded
BYTES_PER_DOF = {("hex", 1): 15e3, ("hex", 2): 15e3, ("tet", 1): 15e3, ("tet", 2): 15e3,
                 ("quad", 1): 4e3, ("quad", 2): 4e3, ("tri", 1): 4e3, ("tri", 2): 4e3}


@dataclass(frozen=True)
class SizeEstimate:
    elements: int
    nodes: int
    dofs: int
    memory_bytes: float
    how: str  # which rule counted (for the message)

    def describe(self) -> str:
        return (f"≈ {self.elements:,} elements, {self.nodes:,} nodes, {self.dofs:,} DOFs, "
                f"≈ {self.memory_bytes / 1e9:.3g} GB ({self.how})")


def _div(length: float, size: float) -> int:
    """lattice.divisions without numpy (and without overflow: a huge count stays a Python int)."""
    return max(1, math.ceil(length / size - 1e-9))


def _structured(n: tuple[int, ...], cell: str, order: int) -> tuple[int, int]:
    elements = math.prod(n) * (6 if cell == "tet" else 2 if cell == "tri" else 1)
    nodes = math.prod((2 if order == 2 else 1) * k + 1 for k in n)
    return elements, nodes


def _divisions(scene) -> tuple[tuple[int, ...], str]:
    spec, mesh = scene.specimen, scene.mesh
    h, hg = mesh.size, mesh.gauge_size or mesh.size
    if spec.shape == "block":
        cut = {"none": 0, "half": 1, "quarter": 2, "eighth": 3}.get(mesh.symmetry, 0)
        n = tuple(_div(s / 2, h) * (1 if a < cut else 2) if cut else _div(s, h) for a, s in enumerate(spec.size))
        return n, "block divisions"
    if spec.shape == "dogbone":
        d = spec.dimensions
        fine = min(d.overall_length, d.parallel_length + 2 * d.transition_length)
        n = (_div(fine, hg) + _div(max(d.overall_length - fine, 0.0), h) if d.overall_length > fine else _div(fine, hg),
             2 * _div(d.width / 2, hg), 2 * _div(d.thickness / 2, min(h, hg)))
        return n, "dogbone mapper divisions"
    if spec.shape == "cruciform":
        d, hm = spec.dimensions, min(h, hg)
        return (_div(2 * d.arm_end, hm), _div(2 * d.arm_end, hm), _div(d.thickness, hm)), "cruciform bounding box"
    if spec.shape == "sheet":
        return (_div(spec.size[0], h), _div(spec.size[1], h)), "sheet divisions"
    raise ValueError(spec.shape)


def _imported(scene) -> tuple[int, int]:
    import numpy as np

    data, order = scene.specimen.data, scene.mesh.order
    nodes, cells = len(data.points), len(data.cells)
    if order == 1:
        return cells, nodes
    pairs = (0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)
    if data.cell == "hex":  # edges ≈ 3 per vertex, faces ≈ 3 per cell in the interior, one node per cell
        return cells, nodes + 3 * nodes + 3 * cells + cells
    edges = np.unique(np.sort(np.concatenate([data.cells[:, list(p)] for p in pairs]), axis=1), axis=0)
    return cells, nodes + len(edges)


def estimate(scene) -> SizeEstimate:
    """The scene's mesh size, counted from its geometry (module docstring)."""
    mesh = scene.mesh
    if scene.specimen.shape == "mesh":
        elements, nodes = _imported(scene)
        how, dim = "the file's own cells", 3
    else:
        n, how = _divisions(scene)
        elements, nodes = _structured(n, mesh.cell, mesh.order)
        dim = len(n)
    dofs = dim * nodes
    memory = BASE_BYTES + BYTES_PER_DOF.get((mesh.cell, mesh.order), 15e3) * dofs
    return SizeEstimate(elements, nodes, dofs, memory, how)


def available_memory() -> float:
    import psutil

    return float(psutil.virtual_memory().available)


def check_budget(scene) -> SizeEstimate:
    """Raise SceneError (naming mesh.size and mesh.max_dofs) if the mesh is beyond the budget."""
    est = estimate(scene)
    limit = scene.mesh.max_dofs or DEFAULT_MAX_DOFS
    what = "mesh.size" if scene.specimen.shape != "mesh" else "specimen.file"
    if est.dofs > limit:
        source = "mesh.max_dofs" if scene.mesh.max_dofs else f"mesh.max_dofs (default {DEFAULT_MAX_DOFS:,})"
        raise SceneError(f"{what} = {scene.mesh.size:g} asks for {est.describe()}: more than {source} = "
                         f"{limit:,} DOFs; use a coarser mesh.size (or raise mesh.max_dofs)")
    free = available_memory()
    if est.memory_bytes > free:
        raise SceneError(f"{what} = {scene.mesh.size:g} asks for {est.describe()}: more than the "
                         f"{free / 1e9:.3g} GB of memory available on this machine; use a coarser mesh.size")
    return est
