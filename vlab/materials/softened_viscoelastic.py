"""Mullins softening and Prony viscoelasticity on one ground law: the softened long-term response
plus Maxwell branches that are not softened (``[effects.viscoelastic]`` with ``[effects.mullins]``).

With ψ0 the ground law (MPa), the Ogden–Roxburgh law M = η ψ0 + φ(η) (vlab.materials.mullins;
state W_max) and the Prony law V = ψ0 + γ ψ_iso + H : E (vlab.materials.viscoelastic; state
Q_i, S_iso) over the same ground law, the incremental potential and its derivatives are

    ψ_inc = M + V − ψ0,     P = η P0 + F (γ S_iso + H),     A = A_M + A_V − A0,

so the stress is the softened ground stress plus the branch stresses, which are Neo-Hookean of μ0
and not softened — the model `vlab fit` fits to rate-dependent cycles with both [model]
viscoelastic and mullins (vlab.identify.records.cyclic), and the one Abaqus describes for its
Mullins effect on a viscoelastic material (applied to the long-term response). The state is the
union of the two laws' (W_max; Q, S_iso: no key in common), each law reading and updating its own
keys; the time step matters for the branches only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from vlab.materials.history import HistoryMaterial, Response, State
from vlab.materials.mullins import OgdenRoxburgh
from vlab.materials.viscoelastic import PronyViscoelastic

__all__ = ["SoftenedViscoelastic"]


@dataclass(frozen=True)
class SoftenedViscoelastic(HistoryMaterial):
    """``mullins`` and ``prony`` must wrap this law's ``elastic`` (module docstring)."""

    mullins: OgdenRoxburgh | None = None
    prony: PronyViscoelastic | None = None

    name: ClassVar[str] = "softened-viscoelastic"

    def __post_init__(self) -> None:
        if self.mullins is None or self.prony is None or not (
                self.mullins.elastic is self.elastic and self.prony.elastic is self.elastic):
            raise ValueError("SoftenedViscoelastic: give an OgdenRoxburgh and a PronyViscoelastic law over its "
                             "own ground law (elastic)")

    def initial_state(self, batch: tuple[int, ...]) -> State:
        return self.mullins.initial_state(batch) | self.prony.initial_state(batch)

    def respond(self, F, state: State, dt: float, with_tangent: bool = True) -> Response:
        m = self.mullins.respond(F, state, dt, with_tangent)
        v = self.prony.respond(F, state, dt, with_tangent)
        e = self.elastic
        tangent = m.tangent + v.tangent - e.tangent(F) if with_tangent else None
        return Response(m.energy + v.energy - e.energy(F), m.stress + v.stress - e.stress(F), tangent)

    def update(self, F, state: State, dt: float) -> State:
        return self.mullins.update(F, state, dt) | self.prony.update(F, state, dt)

    def history_fields(self, state: State, F=None) -> dict:
        """The softening's (max_energy, softening) and the branches' (viscous_stress) fields."""
        return self.mullins.history_fields(state, F) | self.prony.history_fields(state, F)
