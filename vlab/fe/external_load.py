"""Dead external loads (self-weight): f_ext and a body that subtracts its potential.

A dead load does work W_ext = f_extᵀu, so the total potential of the loaded body is
    Π(u) = W(u) − f_extᵀu,      ∂Π/∂u = f_int(u) − f_ext,      ∂²Π/∂u² = K(u)
(the stiffness is unchanged: a dead load does not follow the deformation). The out-of-balance
force f_int − f_ext vanishes on the free DOFs at equilibrium and equals the grip reactions on the
prescribed ones, which is what the load cell reads. Only built when a scene declares a load
effect; otherwise the body is used as it is.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from vlab.fe.assembly import scatter_vector
from vlab.fe.body import LoadWrapper
from vlab.fe.problem import Evaluation
from vlab.fe.space import DisplacementSpace


def body_force_vector(space: DisplacementSpace, b) -> np.ndarray:
    """Consistent nodal forces f_a = ∫ N_a b dV (N) of a uniform body force b (N/mm³, 3 comps)."""
    N = np.stack([np.asarray(phi[0]) for phi in space.basis.basis])  # (a, e, q) values
    weight = np.einsum("aeq,eq->ea", N, space.dx)  # ∫ N_a dV per element, mm³
    fe = weight[:, :, None] * np.asarray(b, dtype=float)[None, None, :]
    return scatter_vector(space, fe)


class LoadedBody(LoadWrapper):
    """A body (hyperelastic or with history) under a dead load f_ext (N); same interface."""

    def __init__(self, body, f_ext: np.ndarray):
        self.inner, self.f_ext = body, np.asarray(f_ext, dtype=float)

    def _loaded(self, ev: Evaluation, u: np.ndarray) -> Evaluation:
        if not ev.admissible:
            return ev
        return replace(ev, W=ev.W - float(self.f_ext @ u), f_int=ev.f_int - self.f_ext)
