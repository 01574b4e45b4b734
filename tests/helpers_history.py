"""Shared helpers of the history-material tests: Taylor remainders, random states, frozen-state adapter."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vlab.materials.history import HistoryMaterial, State

HS = 1e-2 * 0.5 ** np.arange(5)  # h = 1e-2 ... 6.25e-4, halving


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    Q, R = np.linalg.qr(rng.standard_normal((3, 3)))
    Q = Q * np.sign(np.diag(R))
    if np.linalg.det(Q) < 0:
        Q[:, 0] *= -1.0
    return Q


def random_F(rng: np.random.Generator, scale: float) -> np.ndarray:
    while True:
        F = np.eye(3) + scale * rng.standard_normal((3, 3))
        if np.linalg.det(F) > 0.5:
            return F


def taylor_ratios(law: HistoryMaterial, F: np.ndarray, state: State, rng: np.random.Generator,
                  scale: float = 1.0):
    """Remainder ratios r(h)/r(h/2) of energy→stress and stress→tangent (→ 4 for a consistent pair)
    along a random direction dF of entries ~ ``scale``."""
    dF = scale * rng.standard_normal((3, 3))
    base = law.respond(F, state, 1.0)
    r_energy, r_stress = [], []
    for h in HS:
        moved = law.respond(F + h * dF, state, 1.0, with_tangent=False)
        r_energy.append(abs(moved.energy - base.energy - h * np.sum(base.stress * dF)))
        linear = base.stress + h * np.einsum("ijkl,kl->ij", base.tangent, dF)
        r_stress.append(np.linalg.norm(moved.stress - linear))
    r_energy, r_stress = np.array(r_energy), np.array(r_stress)
    return r_energy[:-1] / r_energy[1:], r_stress[:-1] / r_stress[1:]


def assert_quadratic(ratios: np.ndarray) -> None:
    """Remainder ratios of a consistent derivative: → 4 as h → 0 (an inconsistent one gives 2)."""
    assert np.all(ratios > 3.5), ratios
    assert abs(ratios[-1] - 4.0) < 0.1, ratios


@dataclass(frozen=True)
class Frozen:
    """A history law at a frozen state, seen as a hyperelastic model (for vlab.materials.homogeneous)."""

    law: HistoryMaterial
    state: State

    def stress(self, F):
        return self.law.respond(F, self.state, 1.0, with_tangent=False).stress
