"""The tangent K_ff of a state, factorized (or CG + AMG on the iterative path), and the cache
that lets one tangent at a converged state serve the stability check, the next predictor and the
chord steps after it (vlab.fe.newton, vlab.fe.stepping, vlab.checks.monitor)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from vlab.fe.assembly import Partition
from vlab.fe.iterative import AMGConjugateGradient, AMGHierarchy, rigid_body_modes
from vlab.fe.linsolve import Factorization, factorize
from vlab.fe.problem import Evaluation, HyperelasticBody


@dataclass(frozen=True)
class Tangent:
    """A factorized K_ff with its coupling block K_fp (used by the load-step predictor). The full K
    is not kept: its blocks are all any reader needs (the path slope, the grips' rows by symmetry)."""

    factor: Factorization
    Kfp: sp.csr_matrix
    Kff: sp.csr_matrix | None = None  # the free block that ``factor`` stands for, if kept
    Kpp: sp.csr_matrix | None = None  # the prescribed block, if kept (the path slope vᵀKv)


class TangentCache:
    """The tangent of the last state asked for, so that one assembly + factorization at a
    converged state serves the stability check, the next predictor and the chord steps after it.

    A model whose tangent is constant (``material.is_linear``) is factorized once for the whole
    test. ``factorizations`` counts the factorizations made here. With ``linear = "cg-amg"``
    (``use_linear``) the tangent is not factorized: K_ff⁻¹ is CG with the run's one AMG hierarchy
    (``hierarchy``, shared with Newton's corrections and the stability check, rebuilt only on a
    measured slowdown; ``amg_setups`` counts its set-ups)."""

    def __init__(self, body: HyperelasticBody, partition: Partition, linear: str = "direct"):
        self.body, self.partition = body, partition
        self.factorizations = 0
        self.linear = linear
        self._hierarchy: AMGHierarchy | None = None
        self._state: Evaluation | None = None
        self._tangent: Tangent | None = None
        self._constant = body.material is not None and bool(body.material.is_linear)

    def use_linear(self, linear: str) -> None:
        """"direct" or "cg-amg" (vlab.fe.iterative.choose) for the tangents made from now on."""
        self.linear = linear

    @property
    def hierarchy(self) -> AMGHierarchy | None:
        """The shared AMG hierarchy on the iterative path (made on first use), else None."""
        if self.linear != "cg-amg":
            return None
        if self._hierarchy is None:
            self._hierarchy = AMGHierarchy(amg_modes(self.body, self.partition))
        return self._hierarchy

    @property
    def amg_setups(self) -> int:
        return 0 if self._hierarchy is None else self._hierarchy.setups

    def at(self, evaluation: Evaluation) -> Tangent:
        """K, K_ff factorized (or CG + AMG) and K_fp at ``evaluation`` (raises SingularSystem)."""
        if self._tangent is None or not (self._constant or evaluation is self._state):
            # the blocks only: a kept full K was one more 131 MB copy of the matrix beside K_ff
            # at the peak of the 32³ cube's run
            K = self.body.stiffness(evaluation)
            Kff, Kfp = self.partition.blocks(K)
            Kpp = self.partition.prescribed_block(K)
            del K
            if self.linear == "cg-amg":
                factor = AMGConjugateGradient(Kff, hierarchy=self.hierarchy)
            else:
                factor = factorize(Kff)
                self.factorizations += 1
            self._tangent = Tangent(factor, Kfp, Kff, Kpp)
            self._state = evaluation
        return self._tangent

    def holds_any(self) -> Tangent | None:
        """The tangent of the last state asked for (None before the first)."""
        return self._tangent

    def holds(self, evaluation: Evaluation) -> Tangent | None:
        """The cached tangent if it belongs to ``evaluation`` (no new work), else None."""
        if self._tangent is not None and (self._constant or evaluation is self._state):
            return self._tangent
        return None


def amg_modes(body, partition: Partition) -> np.ndarray:
    """The near-nullspace for smoothed aggregation: rigid-body modes on the free DOFs."""
    return rigid_body_modes(body.space.node_coordinates)[partition.free]


def tangent_at(body: HyperelasticBody, partition: Partition, evaluation: Evaluation) -> Tangent:
    Kff, Kfp = partition.blocks(body.stiffness(evaluation))
    return Tangent(factorize(Kff), Kfp)


