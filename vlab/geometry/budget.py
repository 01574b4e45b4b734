"""The size budget: nodes, DOFs and memory of a scene's mesh estimated from its geometry, before
any mesh is built, so that a request the machine cannot hold fails at once with the numbers.

Counts: each shape's registry entry counts its own mesh (``Shape.count(spec, mesh)``, next to its
geometry: vlab/geometry/shapes.py), by arithmetic on the dimensions and no array (the shared rules of
structured lattices in vlab/geometry/counts.py): the block and the strip and shear layers by their
divisions per side, the dogbone and the cruciform by their mappers' divisions, the sheet in 2D, an
imported or CAD mesh by its own nodes and cells. DOFs = nodes × dimension.

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
the cube benchmark (benchmarks/cube_scaling.py, session 10) from above: 7.13 GB measured at
823,875 DOFs (64³ Q1 hexahedra; estimated 7.40 GB), 3.08 GB at 352,947 (48³; est. 3.40 GB).

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
ITERATIVE_BYTES = 8_500.0
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


def estimate(scene, linear_path=None) -> SizeEstimate:
    """The scene's mesh size, counted by its shape's registry entry, and its memory (module
    docstring). ``linear_path(dofs)`` -> "direct" | "cg-amg" says which solver path the run would
    take (vlab.fe.iterative.choose, handed in by the pipeline); None: the direct path."""
    from vlab.geometry.shapes import SHAPES

    mesh = scene.mesh
    count = SHAPES[scene.specimen.shape].count(scene.specimen, mesh)
    dofs = count.dim * count.nodes
    iterative = (linear_path is not None and count.dim == 3 and dofs < 10**15
                 and linear_path(dofs) == "cg-amg")
    return SizeEstimate(count.elements, count.nodes, dofs, _memory(dofs, mesh.cell, mesh.order, iterative),
                        count.how, iterative)


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
