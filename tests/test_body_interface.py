"""Every body the scenes build answers the one body interface (vlab.fe.body), so that no caller
probes it with hasattr/getattr: the optional members exist with their defaults, the history
capability is there exactly when the material remembers, and a dead load forwards its inner body's."""

from __future__ import annotations

import numpy as np
import pytest

from vlab.fe.body import Body, BodyDefaults
from vlab.pipeline.prepare import prepare
from vlab.scene import parse_scene

BASE = {"name": "t", "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
        "mesh": {"size": 5.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.1, "steps": 2}}


def body_of(**changes) -> Body:
    raw = {key: dict(value) if isinstance(value, dict) else value for key, value in BASE.items()}
    for section, table in changes.items():
        raw[section] = raw.get(section, {}) | table
    return prepare(parse_scene(raw)).body


CASES = {
    "hyperelastic": ({}, False, False),
    "mixed": ({"mesh": {"formulation": "mixed"}}, False, False),
    "spring-network": ({"material": {"model": "spring-network"}}, False, False),
    "history": ({"effects": {"viscoelastic": {"tau": [1.0], "beta": [0.5]}},
                 "test": {"ramp_time": 1.0}}, True, False),
    "dead-load": ({"effects": {"gravity": {}}, "material": {"density": 1100}}, False, True),
}


@pytest.mark.parametrize("name", CASES)
def test_every_body_has_every_member_of_the_interface(name):
    changes, remembers, loaded = CASES[name]
    body = body_of(**changes)
    assert isinstance(body, BodyDefaults)
    for member in ("space", "pattern", "material", "f_ext", "history", "tangent_kernel", "evaluate",
                   "stiffness", "cell_cauchy"):
        assert hasattr(body, member), member
    assert (body.history is not None) == remembers
    assert (body.f_ext is not None) == loaded
    assert (body.material is None) == (name == "spring-network")
    assert isinstance(body.tangent_kernel, str)


def test_a_dead_load_forwards_the_inner_bodys_members():
    body = body_of(**CASES["dead-load"][0])
    assert body.space is body.inner.space and body.material is body.inner.material
    assert body.history is body.inner.history and body.tangent_kernel == body.inner.tangent_kernel
    ev = body.evaluate(np.zeros(body.space.n_dofs))
    assert body.cell_cauchy(ev) is None  # the inner hyperelastic body has no cell stress of its own
