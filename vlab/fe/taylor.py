"""Taylor test of a body's energy, force and stiffness: are they each other's derivatives?

Along a direction v, with steps h, h/2, h/4, …:
    r_W(h) = |W(u + h v) − W(u) − h f·v|        = O(h²) if f = ∂W/∂u
    r_f(h) = ‖f(u + h v) − f(u) − h K v‖         = O(h²) if K = ∂f/∂u
The observed order is log2 of the ratio of successive remainders; 2 means consistent, 1 means the
derivative is wrong. Used by the tests and shown in reports for models without a closed-form check.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class TaylorResult:
    h: list[float]
    energy_remainder: list[float]
    force_remainder: list[float]

    @staticmethod
    def _orders(r: list[float]) -> list[float]:
        return [float(np.log2(a / b)) for a, b in zip(r, r[1:]) if a > 0 and b > 0]

    @property
    def energy_order(self) -> float:
        """Median observed order of the energy remainder (2 = f is the gradient of W)."""
        return float(np.median(self._orders(self.energy_remainder)))

    @property
    def force_order(self) -> float:
        """Median observed order of the force remainder (2 = K is the Jacobian of f)."""
        return float(np.median(self._orders(self.force_remainder)))

    def as_dict(self) -> dict:
        return {"h": self.h, "energy_remainder": self.energy_remainder,
                "force_remainder": self.force_remainder,
                "energy_order": self.energy_order, "force_order": self.force_order}


def taylor_test(body, u: np.ndarray, direction: np.ndarray, h0: float, halvings: int = 5) -> TaylorResult:
    """Remainders at h0, h0/2, …; ``u`` must be an admissible state, h0 in mm of ``direction``."""
    ev = body.evaluate(u)
    Kv = body.stiffness(ev) @ direction
    slope = float(ev.f_int @ direction)
    hs, rw, rf = [], [], []
    for i in range(halvings + 1):
        h = h0 / 2**i
        trial = body.evaluate(u + h * direction)
        hs.append(h)
        rw.append(abs(trial.W - ev.W - h * slope))
        rf.append(float(np.linalg.norm(trial.f_int - ev.f_int - h * Kv)))
    return TaylorResult(hs, rw, rf)


def random_state(body, amplitude: float, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A smooth-ish admissible state (small random u) and a random unit direction."""
    rng = np.random.default_rng(seed)
    n = body.space.n_dofs
    u = amplitude * rng.standard_normal(n)
    v = rng.standard_normal(n)
    return u, v / np.linalg.norm(v)
