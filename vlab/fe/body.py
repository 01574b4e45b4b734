"""The body interface: what Newton, the load stepping, the stability checks, the instruments and
post-processing ask of a discretised body, instead of probing it for attributes.

A body maps a displacement vector u (mm, ``space.n_dofs``) to an :class:`Evaluation` (F at the
quadrature points, the energy W in N·mm, the internal force f_int = ∂W/∂u in N, the smallest J)
and an evaluation to the tangent stiffness K = ∂f_int/∂u (N/mm, CSR on ``pattern``). Bodies:
HyperelasticBody, MixedHyperelasticBody, SpringNetwork, HistoryBody, LoadedBody.

Optional members have the defaults of :class:`BodyDefaults`, which every body inherits:
``material`` (the law at the quadrature points; None for the spring network, which has none),
``f_ext`` (a dead load in N; None), ``history`` (the :class:`HistoryCapability` of a body whose
material remembers; None), ``tangent_kernel`` ("numpy", or the compiled kernel's description),
``cell_cauchy`` (a body's own cell-averaged Cauchy stress, None: computed from ``material``) and
``advance`` (None; a body with element unknowns of its own, the mixed body's θ, defines
``advance(evaluation, du, alpha) -> Evaluation``, their Newton update along u + α du, which the
line search calls instead of ``evaluate`` on states that carry them: ``volume_change`` not None),
and ``set_load`` (None; a body whose load is not carried by the prescribed DOFs, the liquid of
vlab.fe.liquid, defines ``set_load(t)``, which the stepper calls with each substep's load
parameter before it evaluates anything there, and ``load_rate(evaluation)``, ∂f/∂t at fixed u
(N), which the load-step predictor adds to the grips' K_fp Δu_p).

An :class:`~vlab.fe.problem.Evaluation` declares the same way what a mixed state adds:
``constraint`` (max |Π v(F) − θ|; 0) and ``volume_change`` (θ − 1; None).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    import scipy.sparse as sp

    from vlab.fe.assembly import SparsityPattern
    from vlab.fe.problem import Evaluation
    from vlab.fe.space import DisplacementSpace

__all__ = ["Body", "HistoryCapability", "BodyDefaults", "LoadWrapper"]


class HistoryCapability(Protocol):
    """A body whose material has internal variables at every quadrature point.

    The stepper calls ``begin_increment(dt)`` (s) before each substep and ``commit(evaluation)``
    once the substep converged and was accepted (a rejected one leaves ``state`` untouched); the
    instruments call ``keep_cells`` at each recorded level, post-processing reads the kept cells."""

    state: dict
    dt: float

    def begin_increment(self, dt: float) -> None: ...
    def commit(self, evaluation: "Evaluation") -> None: ...
    def keep_cells(self, evaluation: "Evaluation") -> None: ...
    def cell_fields_of(self, evaluation: "Evaluation") -> dict[str, np.ndarray] | None: ...
    def cell_history(self, evaluation: "Evaluation") -> dict[str, np.ndarray]: ...


class Body(Protocol):
    space: "DisplacementSpace"
    pattern: "SparsityPattern"
    material: Any
    f_ext: np.ndarray | None
    history: HistoryCapability | None
    tangent_kernel: str

    def evaluate(self, u: np.ndarray) -> "Evaluation": ...
    def stiffness(self, evaluation: "Evaluation") -> "sp.csr_matrix": ...
    def cell_cauchy(self, evaluation: "Evaluation") -> np.ndarray | None: ...


class BodyDefaults:
    """The optional members of :class:`Body` at their defaults (a mixin of every body)."""

    material: Any = None
    f_ext: np.ndarray | None = None
    history: HistoryCapability | None = None
    tangent_kernel: str = "numpy"
    advance = None  # (evaluation, du, alpha) -> Evaluation for a body with element unknowns
    set_load = None  # (t) -> None for a body whose own load depends on the load parameter t
    load_rate = None  # (evaluation) -> ∂f/∂t (N) of such a body
    #: u -> F (d,d,e,q) bit for bit as ``evaluate`` computes it, or None. With it a recorded
    #: load level keeps no F (vlab.fe.stepping.Level.released: 576 B per Q1 hex per level) and
    #: rebuilds it when read; a body that keys data by the identity of an evaluation (history
    #: bodies' kept cell fields) leaves it None
    gradient = None

    def cell_cauchy(self, evaluation: "Evaluation") -> np.ndarray | None:
        return None


class LoadWrapper(BodyDefaults):
    """A body ``inner`` with a load added to its evaluations: a subclass defines
    ``_loaded(evaluation, u) -> Evaluation`` (its energy and force with the load) and, where the
    load changes the tangent, ``stiffness``; everything else is the inner body's
    (vlab.fe.external_load.LoadedBody, vlab.fe.liquid.LiquidBody)."""

    inner: "Body"

    space = property(lambda self: self.inner.space)
    pattern = property(lambda self: self.inner.pattern)
    material = property(lambda self: self.inner.material)
    history = property(lambda self: self.inner.history)
    tangent_kernel = property(lambda self: self.inner.tangent_kernel)
    gradient = property(lambda self: self.inner.gradient)  # a load does not change F

    def cell_cauchy(self, evaluation: "Evaluation") -> np.ndarray | None:
        return self.inner.cell_cauchy(evaluation)

    def evaluate(self, u: np.ndarray) -> "Evaluation":
        return self._loaded(self.inner.evaluate(u), u)

    @property
    def advance(self):
        """The inner body's Newton update of its own element unknowns (the mixed body's θ),
        with the load: None if the inner body has none (``__getattr__`` would hand out the
        inner update without the load)."""
        inner = self.inner.advance
        if inner is None:
            return None
        return lambda ev, du, alpha: self._loaded(inner(ev, du, alpha), ev.u + alpha * du)

    def _loaded(self, ev: "Evaluation", u: np.ndarray) -> "Evaluation":
        raise NotImplementedError

    def stiffness(self, evaluation: "Evaluation"):
        return self.inner.stiffness(evaluation)
