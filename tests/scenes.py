"""Scene builders shared by the tests: a raw scene dict with sensible small defaults."""

from __future__ import annotations

import copy

BASE = {
    "name": "test-block",
    "specimen": {"shape": "block", "size": [10.0, 8.0, 6.0]},
    "mesh": {"size": 5.0, "order": 1, "cell": "hex"},
    "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
    "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.3, "steps": 4},
}


def scene_dict(**sections) -> dict:
    """BASE with sections updated key by key, e.g. scene_dict(test={"stretch": 0.8})."""
    data = copy.deepcopy(BASE)
    for name, values in sections.items():
        if isinstance(values, dict):
            data.setdefault(name, {}).update(values)
        else:
            data[name] = values
    return data
