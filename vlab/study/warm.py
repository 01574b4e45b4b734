"""Compile a scene's kernels before its run is timed, so a study times the solve, not numba.

vlab's compiled kernels (vlab.fe.compiled: F, internal force, tangent per element type and
serial/threaded variant; vlab.tensor's inverse for mesh-sized batches) compile on their first
call, or load from numba's on-disk cache (~10 ms). A cold first compile costs seconds to tens of
seconds (a P2 tet block of a cost study: 43 s of its 44.6 s "mesh" time, measured under load on
the shared 2-core machine, 0.04 s on the second run), and a study that timed it would book it as
the first run's mesh time and bias its recommendation against the element that compiled last.

``warm_kernels(scene)`` builds the scene's specimen and body and evaluates the internal force
and the tangent once at u = 0: exactly the kernels, sizes and thread split the run will call.
Its time (compilation or cache loading, plus one mesh build and one assembly) is returned so
that a study reports it separately. Once per process and element kind: a study's later runs of
the same kind find the kernels compiled (Dask workers are processes: each warms once).
"""

from __future__ import annotations

import time

import numpy as np

_WARM: set[tuple] = set()


def kernel_kind(scene) -> tuple:
    """What decides which kernels a run compiles: element, formulation, model, specimen shape."""
    mesh = scene.mesh
    return (mesh.cell, mesh.order, mesh.formulation, scene.material.model, scene.specimen.shape)


def warm_kernels(scene) -> float:
    """Seconds spent compiling (or loading) the kernels of ``scene``'s run; 0 if already warm."""
    kind = kernel_kind(scene)
    if kind in _WARM:
        return 0.0
    from vlab.fe.space import DisplacementSpace
    from vlab.run import build_specimen, make_body

    start = time.perf_counter()
    specimen = build_specimen(scene)
    space = DisplacementSpace.build(specimen.mesh, scene.mesh.order, specimen.sheet_thickness or 1.0)
    body = make_body(scene, space)
    evaluation = body.evaluate(np.zeros(space.n_dofs))
    if evaluation.admissible:
        body.stiffness(evaluation)
    _WARM.add(kind)
    return time.perf_counter() - start
