"""A rejected (cut-back) substep must leave the quadrature-point history untouched: the retry
starts from the state of the last accepted substep, and the committed result is that of the
accepted substeps only."""

from __future__ import annotations

import numpy as np

from tests.effects_helpers import scene
from vlab.fe import stepping as stepping_module
from vlab.run import run_scene


def test_a_rejected_plastic_substep_leaves_the_history_state_untouched(monkeypatch):
    s = scene({"stretch": 1.05, "steps": 2}, {"plasticity": {"yield_stress": 0.1, "hardening_modulus": 1.0}})
    seen = {"calls": 0}
    original = stepping_module.run_schedule

    def forcing_a_cutback(system, stepping, on_level=None):
        body = system.body

        def accept(candidate, t):
            seen["calls"] += 1
            if seen["calls"] == 1:  # the first converged substep (into the plastic range): reject it
                seen["before"] = {k: v.copy() for k, v in body.state.items()}
                seen["would_be"] = body.material.update(candidate.F, body.state, body.dt)
                return "forced cutback (test)"
            if seen["calls"] == 2:  # the retry with half the increment sees the old state
                seen["at_retry"] = {k: v.copy() for k, v in body.state.items()}
            return stepping.accept(candidate, t) if stepping.accept else None
        return original(system, stepping.__class__(**{**stepping.__dict__, "accept": accept}), on_level)

    monkeypatch.setattr("vlab.pipeline.solve.run_schedule", forcing_a_cutback)
    r = run_scene(s)
    assert r.converged and r.history.levels[0].cutbacks == 1
    assert np.max(seen["would_be"]["alpha"]) > 0.0  # the rejected substep was plastic
    for key, value in seen["before"].items():
        np.testing.assert_array_equal(seen["at_retry"][key], value)
        assert not np.array_equal(seen["would_be"][key], value)
    # and the end result is that of the accepted path: a cut-back-free run reaches the same α
    # (radial uniaxial loading: the return map is exact for any step size)
    plain = run_scene(s)
    np.testing.assert_allclose(r.solver.body.state["alpha"], plain.solver.body.state["alpha"], rtol=1e-9)
