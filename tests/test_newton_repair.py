"""Exact Newton stays exact on benign problems; an indefinite tangent triggers the recorded repair."""

from dataclasses import dataclass

import numpy as np
import pytest
import scipy.sparse as sp

from scenes import scene_dict
from vlab.fe.system import System
from vlab.fe.newton import NewtonOptions, solve_equilibrium
from vlab.fe.problem import Evaluation
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import parse_scene
from vlab.fe.body import BodyDefaults


class DoubleWell(BodyDefaults):  # a body: the optional members at their defaults (vlab.fe.body)
    """W(u) = Σ_i (u_i² − 1)² / 4 + c/2 Σ_i (u_{i+1} − u_i)²: minima near u = ±1, and a tangent
    K = diag(3u² − 1) + c L that is indefinite wherever |u_i| < 1/√3 (a non-convex energy, as a
    softening material beyond its limit point)."""

    def __init__(self, n: int, coupling: float = 0.05):
        self.n = n
        self.L = coupling * sp.diags([2.0 * np.ones(n), -np.ones(n - 1), -np.ones(n - 1)], [0, 1, -1]).tocsr()

    def evaluate(self, u: np.ndarray) -> Evaluation:
        W = float(np.sum((u**2 - 1.0) ** 2) / 4.0 + 0.5 * u @ (self.L @ u))
        f = u**3 - u + self.L @ u
        return Evaluation(u.copy(), np.eye(3)[:, :, None, None], W, f, 1.0, (0, 0))

    def stiffness(self, ev: Evaluation) -> sp.csr_matrix:
        return (sp.diags(3.0 * ev.u**2 - 1.0) + self.L).tocsr()


@dataclass(frozen=True)
class AllFree:
    free: np.ndarray
    prescribed: np.ndarray

    def blocks(self, K):
        return K, K[:, :0]


def test_an_indefinite_tangent_is_repaired_recorded_and_the_solve_still_converges():
    n = 6
    body, partition = DoubleWell(n), AllFree(np.arange(n), np.array([], dtype=np.int64))
    u0 = np.full(n, 0.3)  # K = diag(-0.73) + c L: negative definite
    start = body.evaluate(u0)
    K = body.stiffness(start).toarray()
    r = start.f_int
    newton = np.linalg.solve(K, -r)
    assert np.all(np.linalg.eigvalsh(K) < 0) and r @ newton > 0  # the Newton step goes uphill
    found = solve_equilibrium(System(body, partition, None, (1.0, 1.0)), start, NewtonOptions(rtol=1e-12))
    ev, record = found.evaluation, found.record
    assert record.converged and record.repairs >= 1
    assert np.all(np.abs(ev.u) > 0.9) and ev.W < start.W  # out of the non-convex region, downhill
    assert np.all(np.linalg.eigvalsh(body.stiffness(ev).toarray()) > 0)


def test_a_convex_start_needs_no_repair_and_converges_quadratically():
    body, partition = DoubleWell(6), AllFree(np.arange(6), np.array([], dtype=np.int64))
    found = solve_equilibrium(System(body, partition, None, (1.0, 1.0)), body.evaluate(np.full(6, 1.4)),
                              NewtonOptions(rtol=1e-14))
    ev, record = found.evaluation, found.record
    assert record.converged and record.repairs == 0 and all(a == 1.0 for a in record.step_lengths)
    r = [x for x in record.residuals if x > 1e-13]
    assert np.log(r[-1] / r[-2]) / np.log(r[-2] / r[-3]) > 1.8


@pytest.mark.parametrize("cell, order", [("hex", 1), ("tet", 2)])
def test_benign_tests_use_exact_newton_with_quadratic_convergence(cell, order):
    data = result_to_dict(run_scene(parse_scene(scene_dict(
        mesh={"cell": cell, "size": 5.0, "order": order}, test={"stretch": 1.5, "steps": 3, "grips": "clamped"},
        solver={"rtol": 1e-12, "newton": "exact"}))))
    assert data["converged"] and sum(data["solver"]["repairs"]) == 0
    orders = [p for p in data["solver"]["observed_order"] if p is not None]
    assert orders and min(orders) > 1.8
