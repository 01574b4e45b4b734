"""Cook's membrane: the set-up reproduces the literature, and volumetric locking stays cured.

Fast tests use coarse levels; the full convergence study (vlab.verification.cooks_membrane.run_study,
minutes) is marked slow."""

import numpy as np
import pytest

from vlab.verification.cooks_membrane import (GALLERY_TIP_NU_03, CookCase, StudyPlan, edge_traction,
                                         membrane_mesh, reference_tip, run_study, solve_cook, table)
from vlab.fe.space import DisplacementSpace

# Plane-strain ν = 0.4999 reference: the study's finest Q2/P1dc run (16 × 16), measured with
# run_study(); see reports/cooks-membrane/table.md.
TIP_NU_4999 = 11.48


def test_panel_geometry_and_total_load():
    mesh = membrane_mesh(4)
    corners = {(0.0, 0.0), (48.0, 44.0), (48.0, 60.0), (0.0, 44.0)}
    xy = {(round(x, 9), round(y, 9)) for x, y in mesh.p[:2].T}
    assert corners <= xy
    space = DisplacementSpace.build(mesh, 2)
    f = edge_traction(space, 1.0 / 16.0)
    assert f[1::3].sum() == pytest.approx(1.0, rel=1e-12) and not f[0::3].any() and not f[2::3].any()


@pytest.mark.parametrize("order,divisions", [(1, 8), (2, 4)])
def test_free_slab_reproduces_the_deal_ii_code_gallery(order, divisions):
    """Same energy, load, geometry and (free) z faces as Pelteret & McBride (2016), ν = 0.3."""
    result = solve_cook(CookCase(0.3, "displacement", order, divisions, plane_strain=False))
    assert result.tip_uy == pytest.approx(GALLERY_TIP_NU_03[order][divisions], abs=0.01)


def test_locking_at_nu_4999_and_its_cure_on_coarse_meshes():
    """Q1 displacement stalls far below the reference; Q1/P0 and Q2/P1dc do not."""
    q1 = [solve_cook(CookCase(0.4999, "displacement", 1, n)).tip_uy for n in (2, 4)]
    q1p0 = [solve_cook(CookCase(0.4999, "mixed", 1, n)).tip_uy for n in (2, 4)]
    q2p1 = solve_cook(CookCase(0.4999, "mixed", 2, 2)).tip_uy
    assert max(q1) < 0.45 * TIP_NU_4999            # locked: the displacement model stalls
    assert q1[1] - q1[0] < 0.05 * TIP_NU_4999      # ... and refining barely helps
    assert q1p0[1] > q1p0[0] and q1p0[1] > 0.8 * TIP_NU_4999
    assert q2p1 == pytest.approx(TIP_NU_4999, rel=0.02)


@pytest.mark.slow
def test_convergence_study_displacement_stalls_and_mixed_converges():
    results = run_study(StudyPlan())
    assert all(r.tip_uy is not None for r in results), [r.failure for r in results if r.failure]
    ref, _ = reference_tip(results, 0.4999)
    assert ref == pytest.approx(TIP_NU_4999, rel=0.01)
    series = {(r.nu, r.formulation, r.order): [] for r in results}
    for r in sorted(results, key=lambda r: r.divisions):
        series[(r.nu, r.formulation, r.order)].append(r.tip_uy)
    assert series[(0.4999, "displacement", 1)][-1] < 0.8 * ref      # still locked at 32 × 32
    for order in (1, 2):
        errors = np.abs(np.array(series[(0.4999, "mixed", order)]) - ref)
        assert errors[-2] < 0.02 * ref
    for order in (1, 2):  # ν = 0.3: both formulations converge to the same value
        assert series[(0.3, "displacement", order)][-1] == pytest.approx(reference_tip(results, 0.3)[0], rel=0.01)
    assert "reference" in table(results)
