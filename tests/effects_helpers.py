"""Scenes and oracles shared by the effects tests."""

from __future__ import annotations

import copy

import numpy as np
from scipy.optimize import brentq

from vlab.scene import parse_scene

E, NU = 10.0, 0.3

BLOCK = {
    "name": "ve-block",
    "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
    "mesh": {"size": 10.0, "cell": "hex"},  # one Q1 element: the roller test is homogeneous
    "material": {"model": "neo-hookean", "E": E, "nu": NU},
    "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.2, "steps": 10},
    "measure": {"modulus_points": 0},
}


def scene(test: dict | None = None, effects: dict | None = None, material: dict | None = None, **top):
    data = copy.deepcopy(BLOCK)
    data["test"].update(test or {})
    data["material"].update(material or {})
    if effects is not None:
        data["effects"] = effects
    for key, value in top.items():
        data.setdefault(key, {}).update(value) if isinstance(value, dict) else data.update({key: value})
    return parse_scene(data)


def loop_area(x, y) -> float:
    """|∮ y dx| of a closed polyline (shoelace), the origin prepended."""
    x, y = np.concatenate([[0.0], x]), np.concatenate([[0.0], y])
    return 0.5 * abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))


def point_uniaxial_history(law, stretches, times):
    """The same discrete law integrated at one point in uniaxial stress: F = diag(λ, t, t) with
    P22 = 0 solved at every level, the state committed after each. Returns P11 per level."""
    state, clock, out = law.initial_state(()), 0.0, []
    for lam, time in zip(stretches, times):
        dt = time - clock

        def p22(t):
            return float(law.respond(np.diag([lam, t, t]), state, dt, with_tangent=False).stress[1, 1])

        t = brentq(p22, 0.3, 3.0, xtol=1e-15, rtol=4 * np.finfo(float).eps)
        F = np.diag([lam, t, t])
        out.append(float(law.respond(F, state, dt, with_tangent=False).stress[0, 0]))
        state, clock = law.update(F, state, dt), time
    return np.array(out)
