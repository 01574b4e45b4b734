"""Inversion end to end: a load that must crush elements stops with where and how badly."""

import numpy as np

from helpers_scenes import block_scene
from vlab.fe.assembly import Partition
from vlab.fe.newton import NewtonOptions
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.fe.system import System
from vlab.fe.stepping import Stepping, run_schedule
from vlab.loading.grips import grip_loading
from vlab.materials import make_material
from vlab.run import build_specimen


def test_pushing_a_grip_through_the_specimen_stops_with_element_point_and_min_J():
    scene = block_scene("neo-hookean", 0.5, grips="clamped", size=5.0)
    spec = build_specimen(scene)
    space = DisplacementSpace.build(spec.mesh, 1)
    body = HyperelasticBody(space, make_material("neo-hookean", 5.77, 3.85))
    # grip stretch -0.2: the moving grip ends up beyond the fixed one, no admissible state exists
    loading = grip_loading(spec, space.node_coordinates, (-0.2,), "clamped")
    partition = Partition.build(body.pattern, loading.prescribed)
    history = run_schedule(System(body, partition, loading.u_hat, (1e-12, 17.3)),
                           Stepping(np.array([1.0]), max_cutbacks=6, newton=NewtonOptions(max_iterations=15)))
    failure = history.failure
    assert failure is not None and failure.t_converged < 1.0 / 1.2  # the grips meet at t = 1/1.2
    assert failure.t_attempted > failure.t_converged
    assert failure.min_J is not None and failure.min_J <= 0.0
    assert 0 <= failure.element < space.basis.nelems and 0 <= failure.quadrature_point < space.dx.shape[1]
    assert "inverted" in failure.reason or "admissible" in failure.reason
