"""Every scene in specimens/ runs as a test, on a coarser mesh and fewer steps than its own."""

import json
import tomllib
from functools import cache
from pathlib import Path

import pytest

from golden import differences, golden_path, golden_view

from vlab.report.explain import viscoelastic_apparent
from vlab.report.writer import write_run
from vlab.run import run_scene
from vlab.scene import apply_overrides, parse_scene
from vlab.scene.coarse import coarse_overrides

FILES = sorted((Path(__file__).resolve().parents[1] / "specimens").glob("*.toml"))


def coarse(raw: dict) -> dict:
    """Up to twice the element size (keeping two elements across the narrowest width), at most
    four regular steps: vlab.scene.coarse, the budget the docs gallery runs with too."""
    return apply_overrides(raw, coarse_overrides(raw, FILES[0].parent))


def skip_without_gmsh(path: Path) -> None:
    from vlab.geometry.cad import gmsh_version

    shape = tomllib.loads(path.read_text(encoding="utf-8"))["specimen"]["shape"]
    if shape == "cad" and gmsh_version() is None:
        pytest.skip("the 'cad' extra (gmsh) is not installed: pip install \"vlab[cad]\"")


def test_the_folder_holds_scenes():
    assert len(FILES) >= 8


@cache
def _run_once(path: Path, folder: Path):
    raw = tomllib.loads(path.read_text(encoding="utf-8"))
    scene = parse_scene(coarse(raw), origin=path.name, base_dir=path.parent)
    result = run_scene(scene)
    data = write_run(result, folder / scene.name, path.read_text(encoding="utf-8"))
    return scene, result, data


def run_coarse(path: Path, folder: Path):
    """(scene, result, results.json dict) of one specimen file on its coarse mesh; run once per
    session, shared by the tests below."""
    return _run_once(path, folder)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("specimens")


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_specimen_file_runs_on_a_coarse_mesh(path, folder):
    skip_without_gmsh(path)
    scene, result, data = run_coarse(path, folder)
    assert result.converged, result.history.failure
    moduli, measured = scene.material.moduli, data["measured"]
    E_in, nu_in = moduli.E, moduli.nu
    apparent = viscoelastic_apparent(data)
    if apparent is not None:  # a ramp measures the rate-dependent moduli, which the report states
        E_in, nu_in = apparent["E"], apparent["nu"]
    rel = 0.005 if scene.specimen.shape == "cad" else 0.03  # a CAD dumb-bell: like vlab's own, within 0.5 %
    kind = scene.test.kind
    if kind == "simple-shear":
        # the free ends of the layer carry no shear: the nominal stress over the plate reads G a few % low
        assert measured["G"] == pytest.approx(moduli.mu, rel=0.05)
        assert measured["G_fit"]["r2"] > 0.999
    elif kind == "torsion":  # G = (dT/dψ) / J_p, the small-twist slope
        assert measured["G"] == pytest.approx(moduli.mu, rel=rel)
    elif kind == "confined-compression":  # M = K + 4μ/3 and K from the die's homogeneous state
        assert measured["constrained_modulus"] == pytest.approx(moduli.K + 4 * moduli.mu / 3, rel=rel)
        assert measured["bulk_modulus"] == pytest.approx(moduli.K, rel=rel)
    elif kind == "inflation" and scene.specimen.shape == "membrane":  # the pole: equibiaxial
        assert data["reference"]["max_relative_error_pole_stress_fe"] < 0.05
        assert measured["limit_point"] is not None
    elif kind == "inflation":  # thick incompressible sphere: dp/dλ_a = 4μ (1 − (A/B)³) at λ_a = 1
        a, b = scene.specimen.inner_radius, scene.specimen.inner_radius + scene.specimen.thickness
        assert measured["initial_slope"] == pytest.approx(4 * moduli.mu * (1 - (a / b) ** 3), rel=rel)
        assert data["reference"]["max_relative_error_pressure"] < 0.01
    else:
        assert measured["E"] == pytest.approx(E_in, rel=rel)
        assert measured["nu"] == pytest.approx(nu_in, rel=rel)
    if scene.test.kind == "planar":
        assert measured["planar_modulus"] == pytest.approx(moduli.E / (1 - moduli.nu**2), rel=0.03)
    assert data["mesh"]["quality"]["min_quality"] >= scene.mesh.min_quality


@pytest.mark.parametrize("path", [p for p in FILES if p.stem.startswith(("planar-tension", "shear-plates", "double-lap"))],
                         ids=lambda p: p.stem)
def test_planar_and_shear_specimens_report_their_distance_from_the_homogeneous_state(path, folder):
    scene, _, data = run_coarse(path, folder)
    final = data["homogeneity"]["final"]
    if scene.test.kind == "planar":  # the strip's centre is nearly pure shear, its free ends are not
        assert 0 < final["distance_from_pure_shear"] < 0.02
        assert final["nominal_over_pure_shear"] == pytest.approx(1.0, abs=0.05)
    else:  # edge effects: the centre carries more shear stress than the plate's average
        assert 0 < final["distance_from_simple_shear"] < 0.05
        assert 1.0 < final["centre_over_nominal"] < 1.1


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_results_match_the_golden_files_recorded_before_the_restructuring(path, folder):
    """rtol 1e-6: a pure restructuring leaves every number identical (to round-off, 1e-15), while
    a later solver change legitimately moves results at the level of Newton's rtol (1e-8), so the
    tolerance tells a relocation that changed physics from one that did not, without pinning the
    goldens to round-off that any solver improvement would break."""
    skip_without_gmsh(path)
    expected = json.loads(golden_path(path).read_text(encoding="utf-8"))
    found = differences(expected, golden_view(run_coarse(path, folder)[2], expected), rtol=1e-6)
    assert not found, "\n".join(found[:20])
