"""deal.II step-44's block: a nearly incompressible cube partly loaded by a pressure on its top.

The set-up of J-P. Pelteret and A. McBride's tutorial step-44 (after Reese, Wriggers & Reddy,
2000), in mm, N, MPa: the quarter [0, 1]³ mm of a unit block (symmetry planes x = 0 and z = 0),
u_y = 0 on the bottom y = 0, the top y = 1 held in x and z, and a dead pressure p acting
downwards on the top patch x, z < ½ mm (the central quarter of the full block's top face).
Neo-Hookean with the volumetric–isochoric split (SplitNeoHookean, ψ = ½μ(J^(−2/3) I₁ − 3)
+ ¼κ(J² − 1 − 2 ln J)), μ = 80.194 MPa, ν = 0.4999 (κ = 2μ(1 + ν)/(3(1 − 2ν)) ≈ 4.01e5 MPa).
p0 = 4 MPa (step-44's −4/scale² Pa at scale 1e-3, as recalled: not checked here against the
tutorial's source) and the load ratio p/p0 = 80 give p = 320 MPa, ramped in 10 steps; issue 20
measured 221 iterations for this problem with the old iteration, this set-up 225. The quantity of interest is the compression of the block at the
centre of the loaded face, −u_y(0, 1, 0) (mm). Mixed Q1/P0, n elements per edge.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import skfem

from vlab.fe.assembly import Partition
from vlab.fe.mixed import MixedHyperelasticBody
from vlab.fe.newton import NewtonOptions
from vlab.fe.space import DisplacementSpace
from vlab.materials.split import SplitNeoHookean
from vlab.moduli import from_pair
from vlab.verification.dead_load import ramp

MU = 80.194          # MPa
NU = 0.4999
P0 = 4.0             # MPa
LOAD_RATIO = 80.0    # p / p0


@dataclass(frozen=True)
class BlockResult:
    divisions: int
    dofs: int
    compression: float | None   # −u_y at (0, 1, 0), mm; None if the ramp failed
    per_step: list[int]         # Newton iterations of each converged load step
    iterations: int             # all iterations, failed attempts included
    seconds: float
    failure: str = ""


def block_problem(divisions: int, three_field: bool = True):
    """(body, partition, f_total, top-centre node) for the quarter block, n per edge."""
    axis = np.linspace(0.0, 1.0, divisions + 1)
    mesh = skfem.MeshHex.init_tensor(axis, axis, axis)
    space = DisplacementSpace.build(mesh, 1)
    moduli = from_pair({"mu": MU, "nu": NU})
    body = MixedHyperelasticBody(space, SplitNeoHookean(moduli.lmbda, moduli.mu), three_field)
    X = space.node_coordinates
    fixed = [3 * np.flatnonzero(np.isclose(X[:, 0], 0.0)),           # symmetry x = 0: u_x
             3 * np.flatnonzero(np.isclose(X[:, 1], 0.0)) + 1,       # bottom: u_y
             3 * np.flatnonzero(np.isclose(X[:, 2], 0.0)) + 2]       # symmetry z = 0: u_z
    top = np.flatnonzero(np.isclose(X[:, 1], 1.0))
    fixed += [3 * top, 3 * top + 2]                                  # top held in x and z
    partition = Partition.build(body.pattern, np.unique(np.concatenate(fixed)))
    facets = mesh.facets_satisfying(lambda x: np.isclose(x[1], 1.0) & (x[0] < 0.5) & (x[2] < 0.5))
    face = skfem.FacetBasis(mesh, space.basis.elem, facets=facets, intorder=3)
    f = np.zeros(space.n_dofs)
    f[1::3] = -LOAD_RATIO * P0 * skfem.asm(skfem.LinearForm(lambda v, w: v), face)
    centre = int(np.flatnonzero(np.all(np.isclose(X, [0.0, 1.0, 0.0]), axis=1))[0])
    return body, partition, f, centre


def solve_block(divisions: int = 8, steps: int = 10, options: NewtonOptions = NewtonOptions(rtol=1e-9),
                three_field: bool = True) -> BlockResult:
    t0 = time.perf_counter()
    body, partition, f_total, centre = block_problem(divisions, three_field)
    result = ramp(body, partition, f_total, steps, options, length=1.0)
    compression = None if result.failure else float(-result.u[3 * centre + 1])
    return BlockResult(divisions, int(body.space.n_dofs), compression, result.per_step, result.iterations,
                       time.perf_counter() - t0, result.failure)
