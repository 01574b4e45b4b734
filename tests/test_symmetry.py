"""Symmetry reduction ([mesh] symmetry): a reduced model is a part of the full mesh with the normal
displacement zero on the cut planes, and its corrected readings (force × factor, mirrored gauge
marks) equal the full model's to solver precision. Run with -s to see the times and DOFs."""

import time

import numpy as np
import pytest

from vlab.run import build_specimen, run_scene
from vlab.scene import SceneError, parse_scene

LEVELS = ("half", "quarter", "eighth")
SMALL = {"modulus_window": [1e-5, 5e-5]}


def block(grips="clamped", kind="uniaxial", cell="hex", stretch=1.0002):
    return {"name": "b", "specimen": {"shape": "block", "size": [10.0, 6.0, 4.0]},
            "mesh": {"size": 1.0, "cell": cell}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
            "test": {"kind": kind, "grips": grips, "stretch": stretch, "steps": 1}, "measure": SMALL}


def dogbone(cell):
    return {"name": "d", "specimen": {"shape": "dogbone", "standard": "ISO 527-2 1BA"},
            "mesh": {"size": 1.25, "cell": cell}, "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
            "test": {"kind": "uniaxial", "stretch": 1.0002, "steps": 1}, "measure": SMALL}


def cruciform(cell, model):
    return {"name": "c", "specimen": {"shape": "cruciform", "arm_width": 20.0, "arm_length": 30.0,
                                      "gauge_region": 10.0, "fillet_radius": 5.0, "thickness": 2.0,
                                      "grip_length": 10.0},
            "mesh": {"size": 2.5, "cell": cell}, "material": {"model": model, "E": 10.0, "nu": 0.3},
            "test": {"kind": "biaxial", "stretch": [1.0002, 1.0001], "steps": 1}, "measure": SMALL}


CASES = {
    "block-clamped-hex": block(),
    "block-roller-tet": block("roller", cell="tet"),
    "block-biaxial-roller-tet": block("roller", "biaxial", "tet", [1.0002, 1.0001]),
    "dogbone-1BA-hex": dogbone("hex"),
    "dogbone-1BA-tet": dogbone("tet"),
    "cruciform-hex-neo-hookean": cruciform("hex", "neo-hookean"),
    "cruciform-tet-linear": cruciform("tet", "linear"),
}


def readings(raw: dict, symmetry: str) -> tuple[dict, int, float]:
    raw = raw | {"mesh": raw["mesh"] | {"symmetry": symmetry}}
    start = time.perf_counter()
    result = run_scene(parse_scene(raw))
    seconds = time.perf_counter() - start
    assert result.converged
    c = result.curve
    out = {"E": result.constants.E, "nu": result.constants.nu}
    for axis in c.axes:
        out[f"force_{axis}"] = c.force[axis][-1]
        out[f"strain_{axis}"] = c.strain[axis][-1]
    out["thickness_strain"] = c.thickness_strain[-1]
    if result.diagnostics.cruciform is not None:
        out["k_x"] = result.diagnostics.cruciform["final"]["correction_factor_x"]
    return out, result.space.n_dofs, seconds


@pytest.mark.parametrize("case", CASES)
def test_reduced_models_read_what_the_full_model_reads(case):
    full, dofs, seconds = readings(CASES[case], "none")
    print(f"\n{case}: none {dofs} DOFs {seconds:.2f} s")
    for level in LEVELS:
        part, n, t = readings(CASES[case], level)
        worst = max(abs(part[k] - full[k]) / abs(full[k]) for k in full)
        print(f"{case}: {level} {n} DOFs {t:.2f} s (x{seconds / t:.1f} faster), worst relative difference {worst:.1e}")
        assert worst < 1e-6, (level, part, full)
        assert n < dofs


@pytest.mark.parametrize("symmetry, kept", [("half", 2), ("quarter", 4), ("eighth", 8)])
def test_reduced_mesh_is_the_kept_part_with_planes_pinned_normally(symmetry, kept):
    raw = CASES["cruciform-tet-linear"]
    full = build_specimen(parse_scene(raw))
    part = build_specimen(parse_scene(raw | {"mesh": raw["mesh"] | {"symmetry": symmetry}}))
    assert part.mesh.nelements * kept == full.mesh.nelements
    assert np.all(part.mesh.p[0] >= -1e-12)
    assert part.force_factor(0) == {"half": 1, "quarter": 2, "eighth": 4}[symmetry]  # planes parallel to x halve
    from vlab.loading.grips import grip_loading

    X = part.mesh.p.T
    loading = grip_loading(part, X, (1.01, 1.01), "clamped")
    on_plane = np.flatnonzero(np.abs(X[:, 0]) < 1e-9)
    assert set(3 * on_plane) <= set(loading.prescribed) and not loading.u_hat[3 * on_plane].any()


def test_a_set_up_that_is_not_symmetric_is_refused():
    raw = block("clamped", "biaxial", "hex", [1.01, 1.02])
    raw["mesh"]["symmetry"] = "quarter"
    with pytest.raises(SceneError, match="mesh.symmetry must be 'none' for a biaxial block between clamped grips"):
        parse_scene(raw)


def test_symmetry_level_is_validated():
    raw = block()
    raw["mesh"]["symmetry"] = "third"
    with pytest.raises(SceneError, match="mesh.symmetry must be one of none, half, quarter, eighth"):
        parse_scene(raw)
