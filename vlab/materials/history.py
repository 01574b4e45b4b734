"""Materials with memory: internal variables at quadrature points, frozen within a load increment.

A history-dependent law (viscoelasticity, plasticity, the Mullins effect) is integrated in time
by an implicit update from the last converged state ``state_n`` over an increment of ``dt``
seconds. For fixed ``state_n`` and ``dt`` the update defines an *incremental potential*
ψ_inc(F; state_n, dt) (MPa = mJ/mm³) whose derivative is the algorithmic first Piola stress,

    P = ∂ψ_inc/∂F,        A = ∂P/∂F  (the consistent, "algorithmic" tangent),

so Newton's method on the total energy, its energy line search and the Taylor tests work exactly
as for a hyperelastic model. Examples: for a Prony-series viscoelastic solid ψ_inc contains
H_n : E with the frozen history stress H_n; for J2 plasticity ψ_inc is the minimum over the
plastic increment of elastic energy + hardening energy + dissipation; for Ogden–Roxburgh it is
the pseudo-energy η ψ₀ + φ(η).

Shapes follow vlab.materials.base: F is (3, 3, *batch), ψ_inc (*batch), P (3, 3, *batch),
A (3, 3, 3, 3, *batch); every state array has the trailing batch shape (*batch) after any
leading component axes. ``update`` is called once per converged increment and never mutates
its input (a rejected increment must leave ``state_n`` intact).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.base import Material
from vlab.materials.capabilities import LawCapabilities

State = dict[str, np.ndarray]


@dataclass(frozen=True)
class Response:
    """ψ_inc (*batch), P (3,3,*batch) and, when asked for, A (3,3,3,3,*batch)."""

    energy: np.ndarray
    stress: np.ndarray
    tangent: np.ndarray | None = None


@dataclass(frozen=True)
class HistoryMaterial(LawCapabilities):
    """Base of the history-dependent laws; ``elastic`` is the hyperelastic ground law.

    At F = I with a virgin state every law must reduce to the ground law's small-strain response
    (its tangent at rest is what E and ν are measured from at small strain, unless the effect
    itself changes the instantaneous modulus, like a viscoelastic solid loaded fast).
    """

    elastic: Material

    name: ClassVar[str] = "abstract-history"
    is_linear: ClassVar[bool] = False  # a law with memory is never a constant-tangent law

    def initial_state(self, batch: tuple[int, ...]) -> State:  # pragma: no cover - abstract
        """The virgin state (no deformation history) on a batch of points."""
        raise NotImplementedError

    def respond(self, F: np.ndarray, state: State, dt: float,
                with_tangent: bool = True) -> Response:  # pragma: no cover - abstract
        """ψ_inc, P (and A) at trial F for the increment of ``dt`` s from ``state``."""
        raise NotImplementedError

    def update(self, F: np.ndarray, state: State, dt: float) -> State:  # pragma: no cover
        """The converged state at the end of the increment (a new dict; inputs untouched)."""
        raise NotImplementedError
