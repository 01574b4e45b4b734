"""Stage 2 of a run: the load schedule of the test's protocol, solved level by level.

Every converged level is handed to each observer of a list, in order (the stability monitor
first: it vets the state and may have it cut back, then the instruments). Newton's residual is
relative to the grip reaction, floored at the force of a 1e-6 strain (absolute tolerance
rtol·1e-6·μL², far above the round-off of f_int, ~1e-16·μL²) so that a stress-free state reached
again (unloading to stretch 1) still converges.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp

from vlab.checks.admissibility import inadmissible_request
from vlab.checks.conditioning import restrained_but_singular
from vlab.checks.locking import locking_prone
from vlab.checks.monitor import MonitorOptions, StabilityMonitor
from vlab.effects import EFFECTS
from vlab.fe.iterative import decide as decide_linear, supports
from vlab.fe.linsolve import factorization_cost, solver_in_use
from vlab.fe.newton import CHORD_CONTRACTION, NewtonOptions
from vlab.fe.system import System
from vlab.fe.stepping import Failure, Level, SolveHistory, Stepping, run_schedule
from vlab.loading.kinds import kind_of, run_levels
from vlab.loading.restraint import under_constrained_message, unrestrained_modes
from vlab.pipeline.prepare import Prepared
from vlab.scene import Scene

__all__ = ["Observer", "Solved", "stability_monitor", "solve"]

#: called with every converged level, in the order of the list
Observer = Callable[[Level], None]


@dataclass(frozen=True)
class Solved:
    history: SolveHistory
    linear_solver: str  # what Newton's corrections used: "direct" | "cg-amg"
    linear_choice: str = ""  # why (vlab.fe.iterative.decide)


def stability_monitor(prepared: Prepared) -> StabilityMonitor:
    """The monitor that vets every converged state of this test (vlab.checks.monitor)."""
    scene, loading = prepared.scene, prepared.loading
    kind = kind_of(scene.test)
    return StabilityMonitor(prepared.body, prepared.partition, {a: loading.moving_dofs[a] for a in kind.axes},
                            kind, scene.test.targets, _law_label(scene), loading.u_hat,
                            MonitorOptions(eigenvalues=scene.solver.eigenvalues,
                                           limit_points=_watch_limit_points(scene) and loading.liquid is None,
                                           locking_nu=scene.material.moduli.nu if locking_prone(scene) else None))


def solve(prepared: Prepared, monitor: StabilityMonitor, observers: list[Observer]) -> Solved:
    """Run the test's load schedule; a request that cannot be solved at all is a failure at level 0."""
    scene, specimen = prepared.scene, prepared.specimen
    refusal = _refusal(prepared)
    choice = _linear_path(prepared, analyse=refusal is None)  # nothing is solved after a refusal
    linear_solver = choice.path
    if refusal is not None:
        return Solved(SolveHistory(failure=Failure(0, 1.0, 1.0, 0.0, refusal, [])), linear_solver, choice.reason)
    force_floor = 1e-6 * scene.material.moduli.mu * specimen.length_scale**2

    def observe(level: Level) -> None:
        for observer in observers:
            observer(level)

    system = System(prepared.body, prepared.partition, prepared.loading.u_hat,
                    (force_floor, specimen.length_scale), prepared.loading.path)
    history = run_schedule(system, _stepping(scene, monitor, linear_solver), observe)
    # a singular unloaded tangent with the grips holding: ill-conditioning, not a free specimen
    history = restrained_but_singular(history, prepared.body, prepared.partition, prepared.space)
    if history.failure is not None and prepared.loading.liquid is not None:
        from dataclasses import replace

        from vlab.measure.inflation import pressure_maximum_reason

        reason = pressure_maximum_reason(prepared, history.failure)
        if reason is not None:  # the specimen's pressure maximum, not the solver's failure
            history.failure = replace(history.failure, reason=reason)
    return Solved(history, linear_solver, choice.reason)


def _linear_path(prepared: Prepared, analyse: bool = True):
    """The run's linear path (vlab.fe.iterative.decide): above the DOF crossover, PARDISO's
    analysis says whether a factorization is cheap on this mesh's shape (a shell fills like a 2D
    mesh). It analyses the node graph (``_node_graph``), a ninth of K_ff's entries: 1.0 s instead
    of 3.2 s on the 48³ cube, whose 348,142 free DOFs then go to CG + AMG, 0.11 s on the sphere
    octant. Its flops per entry, times 3, came 3-10 % above K_ff's own on the meshes of
    vlab.fe.iterative's table (a node with a prescribed DOF counts as a whole 3 × 3 block; measured:
    2,811 → 3,046 on the sphere octant, 6,039 → 6,491 and 9,016 → 9,882 on the plates, 12,112 →
    12,987 on the 24³ cube, 14,148 → 15,175 on the torsion cylinder, 94,763 → 97,875 on the 48³
    cube), so an error leans to CG + AMG, the path of lower memory."""
    partition = prepared.partition
    return decide_linear(prepared.scene.solver.linear, len(partition.free), solver_in_use(),
                         supports(prepared.body), cost=(lambda: _node_graph_cost(partition)) if analyse else None)


def _node_graph_cost(partition):
    cost = factorization_cost(_node_graph(partition))
    return None if cost is None else cost.of_blocks(3)


def _node_graph(partition) -> sp.csr_matrix:
    """The pattern of K_ff on one DOF per node (the first free one of node i's DOFs 3 i + c): the
    graph of the nodes with a free DOF, each entry standing for a 3 × 3 block of K_ff."""
    n_free = len(partition.free)
    K = sp.csr_matrix((np.ones(len(partition.ff_indices)), partition.ff_indices, partition.ff_indptr),
                      shape=(n_free, n_free))
    node = partition.free // 3  # ascending: a node's free DOFs are neighbours
    first = np.flatnonzero(np.r_[True, node[1:] != node[:-1]])
    return K[first][:, first]


def _stepping(scene: Scene, monitor: StabilityMonitor, linear_solver: str) -> Stepping:
    levels = run_levels(scene)
    return Stepping(
        schedule=levels.t, times=levels.time,
        force_held=levels.force_held if levels.force_held.any() else None,
        force_targets=levels.force,
        max_cutbacks=scene.solver.max_cutbacks,
        newton=NewtonOptions(rtol=scene.solver.rtol, max_iterations=scene.solver.max_iterations,
                             linear=linear_solver,
                             chord_contraction=CHORD_CONTRACTION if scene.solver.newton == "reuse" else 0.0),
        accept=monitor.accept,
        tangents=monitor.tangents,  # the stability check's factorization feeds the next predictor
    )


def _refusal(prepared: Prepared) -> str | None:
    """Why the request cannot be solved at all (rigid-body modes, no admissible state), or None."""
    modes = unrestrained_modes(prepared.space.node_coordinates, prepared.loading.prescribed)
    if modes:
        return under_constrained_message(modes)
    test = prepared.scene.test
    return inadmissible_request(prepared.ground, kind_of(test), test.targets, prepared.scene.specimen.shape)


def _watch_limit_points(scene: Scene) -> bool:
    """A falling force is a limit point only on a monotonic ramp of an elastic material, and not
    on a deliberately imperfect (post-buckled) path: unloading, relaxing, creeping and a bent
    strip's softening are the physics asked for. Instrument noise changes no physics. A kind whose
    grips do not move in proportion to t (torsion's rotating grip) has no load Q = û_p · f conjugate
    to t to watch, nor has a liquid-loaded test (the bulge test: its pressure maximum is measured,
    vlab.measure.inflation.limit_point; the caller checks the loading)."""
    physical = [e for e in scene.effects if EFFECTS[e.name].role != "measure"]
    return (scene.test.protocol.name == "monotonic" and not physical and scene.test.imperfection is None
            and kind_of(scene.test).proportional)


def _law_label(scene: Scene) -> str:
    """The law a stability diagnosis names: the model, or the history law wrapping it."""
    law = next((e.name for e in scene.effects if EFFECTS[e.name].role == "material"), None)
    return scene.material.model if law is None else f"{scene.material.model} with effects.{law}"
