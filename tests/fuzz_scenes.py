"""Random scenes for the fuzz tests and the invariants every outcome must satisfy."""

from __future__ import annotations

import math
import re

import numpy as np
from hypothesis import strategies as st

from vlab.materials.split import SPLIT_LAWS
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import SceneError, parse_scene

MODELS = ("linear", "stvk", "stvk-volumetric", "neo-hookean")
stretches = st.floats(0.2, 5.0, allow_nan=False)
poisson = st.one_of(st.floats(0.0, 0.4999), st.sampled_from([0.0, 0.45, 0.49, 0.499, 0.4999]))


@st.composite
def scenes(draw, mixed_only: bool = False) -> dict:
    """Random block scenes; ``mixed_only`` draws only mesh.formulation = "mixed" (split laws, hexes)."""
    extent = [draw(st.floats(2.0, 20.0)) for _ in range(3)]
    divisions = draw(st.integers(1, 2))
    kind = draw(st.sampled_from(["uniaxial", "biaxial"]))
    if kind == "uniaxial":
        stretch = draw(stretches.filter(lambda s: abs(s - 1.0) > 1e-3))
    else:
        sx = draw(stretches.filter(lambda s: abs(s - 1.0) > 1e-3))
        ratio = draw(st.floats(-1.0, 1.0))  # biaxial ratio: (sy - 1) = ratio (sx - 1)
        stretch = [sx, float(np.clip(1.0 + ratio * (sx - 1.0), 0.2, 5.0))]
    cell = "hex" if mixed_only else draw(st.sampled_from(["hex", "tet"]))
    model = draw(st.sampled_from(tuple(SPLIT_LAWS) if mixed_only else MODELS))
    # the mixed formulation where the scene allows it: a split law on hexes (order 1 here)
    mixed_ok = model in SPLIT_LAWS and cell == "hex"
    formulation = ("mixed" if mixed_only else draw(st.sampled_from(["displacement", "mixed"]))) \
        if mixed_ok else "displacement"
    return {
        "name": "fuzz",
        "specimen": {"shape": "block", "size": extent},
        "mesh": {"size": max(extent) / divisions, "cell": cell, "order": 1, "formulation": formulation},
        "material": {"model": model, "E": draw(st.floats(0.1, 1000.0)),
                     "nu": draw(poisson)},
        "test": {"kind": kind, "grips": draw(st.sampled_from(["roller", "clamped"])),
                 "stretch": stretch, "steps": draw(st.integers(1, 4))},
        "solver": {"max_cutbacks": 6},
    }


def outcome_of(reason: str) -> str:
    for key, label in (("invalid mesh", "refused: invalid mesh"),
                       ("under-constrained", "refused: under-constrained"),
                       ("refused before solving", "refused: no admissible state"),
                       ("load limit point", "stopped: load limit point"),
                       ("loss of stability", "stopped: loss of stability"),
                       ("inverted", "stopped: inversion"),
                       ("line search", "stopped: line search"),
                       ("no convergence", "stopped: no convergence"),
                       ("singular", "stopped: singular tangent")):
        if key in reason:
            return label
    return "stopped: other"


def run_and_check(raw: dict) -> str:
    """Run a raw scene; assert the invariants; return the outcome label."""
    try:
        scene = parse_scene(raw)
    except SceneError as exc:
        assert str(exc)
        return "invalid scene"
    try:
        result = run_scene(scene)
    except SceneError as exc:  # e.g. a mesh below mesh.min_quality, refused before solving
        assert "mesh." in str(exc), str(exc)
        return "refused: mesh below quality threshold"
    data = result_to_dict(result)  # JSON-safe: NaN would have become None
    for name, column in data["curve"].items():
        if name != "units":
            assert all(v is not None and math.isfinite(v) for v in column), name
    for level in result.history.levels:
        ev = level.evaluation
        assert ev.min_J > 0.0 and math.isfinite(ev.W) and ev.W >= -1e-9 * (1 + abs(ev.W))
        assert np.all(np.isfinite(ev.u)) and np.all(np.isfinite(ev.f_int))
    stretch = scene.test.stretch
    same_side = len(stretch) == 1 or (stretch[0] - 1) * (stretch[1] - 1) > 0
    if same_side:
        for axis, s in enumerate(stretch):
            key = "force" if axis == 0 else "force_y"
            assert all(np.sign(f) == np.sign(s - 1.0) for f in data["curve"][key] if abs(f) > 0), key
    if data["converged"]:
        assert data["failure"] is None and len(result.history.levels) > 0
        return "converged"
    reason = data["failure"]["reason"]
    assert isinstance(reason, str) and reason and not re.search(r"\bnan\b", reason.lower())
    return outcome_of(reason)
