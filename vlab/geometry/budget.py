"""The size budget: nodes, DOFs and memory of a scene's mesh estimated from its geometry, before
any mesh is built, so that a request the machine cannot hold fails at once with the numbers.

Counts (no array is allocated; every count is arithmetic on the dimensions):
- block: n_i = ceil(side_i / h) divisions per side (vlab.geometry.lattice.divisions), per half
  side and mirrored for a symmetry-reduced block, which meshes 1/2, 1/4, 1/8 of it;
- dogbone: the structured mapper's divisions: along x ceil(l_fine / h_g) + ceil(l_tabs / h) with
  l_fine = parallel length + 2 × transition, across 2 ceil(w / 2 h_g), through 2 ceil(t / 2 min(h, h_g));
- cruciform: the mapper's octant (central square and two arms, breakpoints at slits, fillets and
  ramps counted as extra divisions), mirrored;
- sheet: n_x n_y quadrilaterals (two triangles each); planar-tension strip, shear layer(s): as a
  block of their dimensions (a double lap: two layers, as one of twice the gap);
- imported mesh: its own nodes and cells (order 2 adds one node per edge, and per face and cell
  for hexahedra).
Structured hexahedra: elements E = Π n_i; vertices Π(n_i + 1); order 2 (Q2, and P2 on the Kuhn
split, which adds the same face and body diagonals' midpoints) Π(2 n_i + 1) nodes. Tetrahedra: 6E
(Kuhn split). DOFs = nodes × dimension.

Memory (bytes), on the direct path ≈ BASE_BYTES + A[(cell, order)] × DOFs^(4/3): the sparse direct
factorization (every converged state is factorized for Newton and the stability check) fills in
as n^(4/3) for a 3D mesh under nested dissection, and dominates; the
coefficients are fitted on the peak RSS (/usr/bin/time) of ``vlab run --no-render --no-estimate``
on a 40 × 20 × 10 mm block at 28,413 DOFs (PARDISO, numba kernels, 2-core machine): hex order 1
844 MB, order 2 1,094 MB; tet order 1 729 MB, order 2 866 MB; base 400 MB (4,158 DOFs: 425 MB).
Checked at 84,960 DOFs (hex order 1): measured 2,180 MB, estimated 2,320 MB (+6 %).

On the iterative path (CG + AMG corrections, LOBPCG stability check: vlab.fe.iterative.choose,
above the direct solver's crossover) nothing is factorized and memory grows linearly:
≈ BASE_BYTES + ITERATIVE_BYTES × r[(cell, order)] × DOFs, r = the tangent's nonzeros per row
relative to Q1 hexahedra (counted on an 8 mm block: Q1 hex 64.3, Q2 hex 147.9, P1 tet 37.4,
P2 tet 70.1; 2D from the stencil sizes), since what is held (the tangents, the AMG hierarchy,
Newton's vectors) is a few copies of the matrix. ITERATIVE_BYTES is fitted on the peak RSS of
the cube benchmark (benchmarks/cube_scaling.py): 1,464 MB at 107,811 DOFs (32³ Q1 hexahedra).

Limits: DOFs ≤ mesh.max_dofs (default DEFAULT_MAX_DOFS) and estimated memory ≤ the memory
available now (psutil), with the numbers in the message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from vlab.fields import SceneError

#: 2 million DOFs is ≈ 130 GB by the memory model below (hex order 1): beyond any one machine
#: vlab is meant for, so on real machines the memory check binds first; the fixed cap keeps a
#: scene's validity from depending only on how much memory happens to be free.
DEFAULT_MAX_DOFS = 2_000_000
BASE_BYTES = 400e6  # python, numpy/scipy, numba, VTK loaded
FILL_EXPONENT = 4.0 / 3.0
#: bytes / DOF^(4/3), fitted at 28,413 DOFs (module docstring); 2D (sheets) fills far less
#: bytes / DOF on the iterative path for Q1 hexahedra, fitted on the cubes' peak RSS (docstring)
ITERATIVE_BYTES = 10_000.0
NONZEROS_RELATIVE = {("hex", 1): 1.0, ("hex", 2): 2.3, ("tet", 1): 0.58, ("tet", 2): 1.09,
                     ("quad", 1): 0.25, ("quad", 2): 0.55, ("tri", 1): 0.2, ("tri", 2): 0.35}
FILL_BYTES = {("hex", 1): 513.0, ("hex", 2): 801.0, ("tet", 1): 380.0, ("tet", 2): 538.0,
              ("quad", 1): 60.0, ("quad", 2): 90.0, ("tri", 1): 45.0, ("tri", 2): 65.0}


@dataclass(frozen=True)
class SizeEstimate:
    elements: int
    nodes: int
    dofs: int
    memory_bytes: float
    how: str  # which rule counted (for the message)
    iterative: bool = False  # memory estimated for the CG + AMG path (no factorization)

    def describe(self) -> str:
        path = "CG + AMG, no factorization" if self.iterative else "sparse factorization"
        return (f"≈ {_count(self.elements)} elements, {_count(self.nodes)} nodes, {_count(self.dofs)} DOFs, "
                f"≈ {self.memory_bytes / 1e9:.3g} GB with the {path} ({self.how})")


def _count(n: int) -> str:
    """1,234,567 below 10^12; 1.23e+15 or 10^906 above (a count may exceed any float)."""
    if n < 10**12:
        return f"{n:,}"
    return f"{float(n):.3g}" if n < 10**300 else f"10^{len(str(n)) - 1}"


_CUT = {"none": 0, "half": 1, "quarter": 2, "eighth": 3}  # mesh.symmetry: planes cut (x, y, z in turn)


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
    cut = _CUT.get(mesh.symmetry, 0)
    if spec.shape == "block":
        n = tuple(_div(s / 2, h) * (1 if a < cut else 2) if cut else _div(s, h) for a, s in enumerate(spec.size))
        return n, "block divisions"
    if spec.shape == "dogbone":
        d = spec.dimensions
        fine = min(d.overall_length, d.parallel_length + 2 * d.transition_length)
        n = (_div(fine, hg) + _div(max(d.overall_length - fine, 0.0), h) if d.overall_length > fine else _div(fine, hg),
             2 * _div(d.width / 2, hg), 2 * _div(d.thickness / 2, min(h, hg)))
        return tuple(-(-k // 2) if a < cut else k for a, k in enumerate(n)), "dogbone mapper divisions"
    if spec.shape == "sheet":
        return (_div(spec.size[0], h), _div(spec.size[1], h)), "sheet divisions"
    if spec.shape == "planar-tension":
        return (_div(spec.height, h), _div(spec.width, h), _div(spec.thickness, h)), "strip divisions"
    if spec.shape in ("shear", "double-lap"):  # a double lap: two layers, counted as one of twice the gap
        layers = 2 if spec.shape == "double-lap" else 1
        return (_div(spec.length, h), layers * _div(spec.gap, h), _div(spec.depth, h)), "layer divisions"
    raise ValueError(spec.shape)


def _cruciform(scene) -> tuple[int, int]:
    """The mapper's octant: a central square of n_e × n_e cells and two arms of n_x × n_e, n_z
    layers, mirrored 8 times (module docstring)."""
    d, mesh = scene.specimen.dimensions, scene.mesh
    h, hg, k = mesh.size, mesh.gauge_size or mesh.size, 2 if mesh.order == 2 else 1
    a, r = d.arm_width / 2, d.fillet_radius
    n_e = _div(a, hg) + 2 * d.slit_count + 2  # breakpoints: gauge region, slit edges, thinning ramp
    n_x = _div(max(r, 1e-300), hg) + _div(max(d.arm_end - a - r, 1e-300), h) + 3
    n_z = _div(d.centre_thickness / 2, min(h, hg))
    cut = _CUT.get(mesh.symmetry, 0)  # planes cut (x, then y, then z): the octant is mirrored across the rest
    copies_plane, copies_z = 4 // (2 ** min(cut, 2)), 1 if cut == 3 else 2
    cells = copies_plane * copies_z * (n_e * n_e + 2 * n_x * n_e) * n_z * (6 if mesh.cell == "tet" else 1)
    plane = copies_plane * ((k * n_e + 1) ** 2 + 2 * k * n_x * (k * n_e + 1))
    return cells, plane * (copies_z * k * n_z + 1)


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


def estimate(scene, linear_path=None) -> SizeEstimate:
    """The scene's mesh size, counted from its geometry, and its memory (module docstring).

    ``linear_path(dofs)`` -> "direct" | "cg-amg" says which solver path the run would take
    (vlab.fe.iterative.choose, handed in by the pipeline); None: the direct path."""
    mesh = scene.mesh
    if scene.specimen.shape in ("mesh", "cad"):  # a CAD file is meshed by Gmsh when the scene is read
        elements, nodes = _imported(scene)
        how, dim = "the file's own cells", 3
    elif scene.specimen.shape == "cruciform":
        elements, nodes = _cruciform(scene)
        how, dim = "cruciform mapper divisions", 3
    else:
        n, how = _divisions(scene)
        elements, nodes = _structured(n, mesh.cell, mesh.order)
        dim = len(n)
    dofs = dim * nodes
    iterative = linear_path is not None and dim == 3 and dofs < 10**15 and linear_path(dofs) == "cg-amg"
    return SizeEstimate(elements, nodes, dofs, _memory(dofs, mesh.cell, mesh.order, iterative), how, iterative)


def _memory(dofs: int, cell: str, order: int, iterative: bool) -> float:
    if dofs >= 10**15:
        return math.inf
    if iterative:
        return BASE_BYTES + ITERATIVE_BYTES * NONZEROS_RELATIVE.get((cell, order), 2.3) * dofs
    return BASE_BYTES + FILL_BYTES.get((cell, order), 801.0) * float(dofs) ** FILL_EXPONENT


def available_memory() -> float:
    import psutil

    return float(psutil.virtual_memory().available)


def check_budget(scene, linear_path=None) -> SizeEstimate:
    """Raise SceneError (naming mesh.size and mesh.max_dofs) if the mesh is beyond the budget;
    ``linear_path`` as for ``estimate``."""
    est = estimate(scene, linear_path)
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
