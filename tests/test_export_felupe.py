"""The exported felupe.py end to end: executed as it is, FElupe's own material equals vlab's.

FElupe (with tensortrax, the `test` extra) evaluates the first Piola–Kirchhoff stress of the
file's ``umat`` at general deformations and at vlab's homogeneous uniaxial states (solved by
vlab.materials.homogeneous): 1e-9 relative to vlab's law; and a FElupe block solve (a cube in
uniaxial tension with free lateral faces, fem.dof.uniaxial) reaches vlab's homogeneous state:
the same lateral stretch and nominal stress to 1e-9.
"""

from __future__ import annotations

import numpy as np
import pytest

from export_cases import LABELS, TABLES, base_card
from vlab.export import EXPORTERS
from vlab.export.card import material_table
from vlab.export.header import UNITS
from vlab.materials.card import build_material, parse_material
from vlab.materials.homogeneous import uniaxial

fem = pytest.importorskip("felupe", reason="FElupe is not installed (pip install vlab[test])")
pytest.importorskip("tensortrax", reason="FElupe's hyperelastic models need tensortrax (pip install vlab[test])")

CASES = [(l, v) for l in LABELS for v in (("quadratic", "log", "simo-taylor") if l != "neo-hookean" else (None,))]


def _umat(card):
    namespace: dict = {}
    exec(compile(EXPORTERS["felupe"].write(card, UNITS["mm"]), "felupe.py", "exec"), namespace)
    return namespace["umat"]


def _P(umat, F):
    """FElupe's P at F (3, 3, n) -> (3, 3, n)."""
    return umat.gradient([F[:, :, None, :], None])[0][:, :, 0, :]


def _deformations(n=6, seed=3):
    rng = np.random.default_rng(seed)
    F = np.eye(3)[:, :, None] + 0.25 * rng.standard_normal((3, 3, n))
    return F[:, :, np.linalg.det(np.moveaxis(F, -1, 0)) > 0.2]


@pytest.mark.parametrize("label,volumetric", CASES)
def test_felupes_stress_of_the_exported_file_equals_vlabs(label, volumetric):
    card = base_card(label, volumetric)
    law = build_material(parse_material(material_table(card)))
    umat = _umat(card)
    F = _deformations()
    if card.model == "gent":  # inside the chains' limit
        F = np.eye(3)[:, :, None] + 0.4 * (F - np.eye(3)[:, :, None])
    got, want = _P(umat, F), np.asarray(law.stress(F))
    assert np.allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())
    for state in _homogeneous(law):
        P = _P(umat, state.F[:, :, None])[:, :, 0]
        assert abs(P[0, 0] / state.nominal_stress - 1) < 1e-9
        assert np.allclose(P, state.P, rtol=0, atol=1e-9 * abs(state.nominal_stress))


def _homogeneous(law):
    """vlab's homogeneous uniaxial (tension and compression), equibiaxial and planar states."""
    from vlab.materials.homogeneous import biaxial, planar

    for lam in (0.7, 1.6, 2.4):
        yield uniaxial(law, lam)
        yield biaxial(law, lam, lam)
        yield planar(law, lam)


@pytest.mark.parametrize("label", ["mooney-rivlin", "ogden-3"])
def test_a_felupe_block_solve_with_the_exported_file_reaches_vlabs_homogeneous_state(label):
    card = base_card(label, "quadratic")
    law = build_material(parse_material(material_table(card)))
    umat = _umat(card)
    mesh = fem.Cube(n=2)
    field = fem.FieldContainer([fem.Field(fem.RegionHexahedron(mesh), dim=3)])
    boundaries, _ = fem.dof.uniaxial(field, clamped=False, move=0.6, return_loadcase=True)
    solid = fem.SolidBody(umat, field)
    step = fem.Step(items=[solid], ramp={boundaries["move"]: np.linspace(0, 0.6, 7)[1:]}, boundaries=boundaries)
    fem.Job(steps=[step]).evaluate(tol=1e-13, verbose=0)
    F = field.extract()[0]
    state = uniaxial(law, 1.6)
    assert np.allclose(F[0, 0], 1.6, rtol=1e-12)
    assert np.allclose(F[1, 1], state.lateral_stretch, rtol=1e-9)
    P = umat.gradient([F, None])[0]
    assert np.allclose(P[0, 0], state.nominal_stress, rtol=1e-9)


def test_the_shipped_treloar_felupe_file_runs_and_gives_the_fits_stress():
    from pathlib import Path

    folder = Path(__file__).resolve().parents[1] / "specimens" / "treloar1944" / "cards"
    ns: dict = {}
    exec(compile((folder / "felupe.py").read_text(), "felupe.py", "exec"), ns)
    import tomllib

    law = build_material(parse_material(tomllib.loads((folder / "card.toml").read_text())["material"]))
    state = uniaxial(law, 5.0)
    P = _P(ns["umat"], state.F[:, :, None])[:, :, 0]
    assert abs(P[0, 0] / state.nominal_stress - 1) < 1e-9
