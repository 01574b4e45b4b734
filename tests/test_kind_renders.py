"""The renders of the new kinds draw what the lab would see: the confined-compression die and its
platens (the moving platen on the compressed end), the twisted cylinder coloured by the shear
strain, and the interactive view's levels named by the kind's control, starting at its peak."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest

from vlab.render.camera import fit_camera
from vlab.report.interactive import model_payload
from vlab.report.outcome import outcome_of
from vlab.run import run_scene
from vlab.scene import parse_scene

RADIUS, LENGTH, LAM, PSI = 2.0, 4.0, 0.8, 0.1


@cache
def snapshot(kind: str):
    test = ({"kind": "confined-compression", "grips": "die", "stretch": LAM} if kind == "die" else
            {"kind": "torsion", "twist": PSI})
    raw = {"name": kind, "specimen": {"shape": "cylinder", "radius": RADIUS, "length": LENGTH},
           "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.45},
           "test": test | {"steps": 2}}
    return outcome_of(run_scene(parse_scene(raw))).snapshot


def test_the_die_stays_and_the_moving_platen_follows_the_compressed_end():
    snap = snapshot("die")
    parts = {p.name: p for p in snap.fixtures}
    assert set(parts) == {"die", "fixed platen", "moving platen"}
    die = parts["die"]
    assert np.all(die.displacement == 0.0) and die.opacity < 1.0
    r = np.hypot(die.points[:, 1], die.points[:, 2])
    assert r == pytest.approx(np.full(len(r), r[0])) and r[0] > RADIUS  # drawn just outside the bore
    assert np.ptp(die.points[:, 0]) > LENGTH  # it runs past both platens
    np.testing.assert_allclose(parts["moving platen"].displacement[-1], [(LAM - 1.0) * LENGTH, 0.0, 0.0],
                               atol=1e-9 * LENGTH)
    np.testing.assert_allclose(parts["fixed platen"].displacement, 0.0, atol=1e-9 * LENGTH)


def test_the_render_frames_the_die_and_the_3d_view_draws_it():
    from vlab.render.specimens import framed_points

    snap = snapshot("die")
    alone = fit_camera(np.vstack([snap.points, snap.points + snap.displacement[-1]]))
    framed = fit_camera(np.vstack(framed_points(snap, [snap.n_frames - 1])))
    assert framed.extent[0] > alone.extent[0]  # the platens and the die are in the picture
    payload = model_payload(snap)
    assert [f["name"] for f in payload["fixtures"]] == ["die", "fixed platen", "moving platen"]
    assert payload["fixtures"][2]["move"][-1][0] == pytest.approx((LAM - 1.0) * LENGTH)
    assert payload["levels"][-1].startswith(f"platen stretch {LAM:.4g}")


def test_the_3d_view_of_a_twist_starts_at_the_largest_twist_and_names_it():
    snap = snapshot("torsion")
    payload = model_payload(snap)
    assert payload["start"] == len(payload["levels"]) - 1  # the largest |ψ − 0|, not |ψ − 1|
    assert payload["levels"][-1].startswith(f"twist (rad/mm) {PSI:.4g}")
    assert payload["fixtures"] == []


def test_a_torsion_report_is_coloured_by_the_shear_strain_of_the_surface(tmp_path):
    """Each section is in simple shear γ = ψ r, so a cell's λ₁ − λ₃ is ψ times its mean radius
    (within 10 % on this coarse, compressible cylinder, ν = 0.45, away from the clamped ends'
    cells and the axis), and the report's render uses that field."""
    from vlab.report.writer import ReportOptions, write_report

    snap = snapshot("torsion")
    corners = snap.points[snap.mesh.t]  # (corners, cells, 3)
    radius = np.hypot(corners[..., 1], corners[..., 2]).mean(axis=0)
    outer = radius > 0.5 * RADIUS
    np.testing.assert_allclose(snap.fields["max-shear"][-1][outer], PSI * radius[outer], rtol=0.1)
    raw = {"name": "torsion", "specimen": {"shape": "cylinder", "radius": RADIUS, "length": LENGTH},
           "mesh": {"size": 1.0, "cell": "hex"}, "material": {"model": "neo-hookean", "E": 3.0, "nu": 0.45},
           "test": {"kind": "torsion", "twist": PSI, "steps": 2}}
    outcome = outcome_of(run_scene(parse_scene(raw)))
    summary = write_report([outcome], tmp_path / "r", parse_scene(raw), None, ReportOptions(vtu=False))
    assert summary["renders"]["side_by_side"]["file"] == "render_max-shear.png"
    page = (tmp_path / "r" / "index.html").read_text(encoding="utf-8")
    assert "max shear strain" in page and "twist farthest from rest" in page
