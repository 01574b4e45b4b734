"""The DIC Challenge 2.0 metrics of a scene's own camera (vlab.dic.resolution, vlab.dic.instrument):
the spatial resolution against the closed form of an affine subset (Reu et al. 2022), its response
to the subset size together with the noise floor's, the MEI, and metrics = "basic"."""

from __future__ import annotations

import numpy as np
import pytest

from vlab.dic.correlate import Settings
from vlab.dic.resolution import box_ratio, theory


def test_the_closed_form_is_the_papers():
    """Reu et al. 2022 give 67.8 px as the theoretical displacement spatial resolution of a 17 px
    affine subset; the Dirichlet kernel is 1 at long periods and 0 at the subset's own period."""
    assert theory(Settings(subset=17))["displacement_px"] == pytest.approx(67.8, abs=0.05)
    assert box_ratio(17, 1e6) == pytest.approx(1.0, abs=1e-9)
    assert abs(box_ratio(17, 17.0)) < 1e-12


def _record(subset: int, metrics: str = "full", face: str = "top"):
    import skfem

    from vlab.dic.instrument import build_view, record
    from vlab.scene.instruments import FACES, DicSpec

    # a block 40 × 16 × 8 mm; the camera (0.1 mm/px, noise 0.5 % of full scale) sees only the face
    mesh = skfem.MeshHex.init_tensor(np.linspace(0, 40, 21), np.linspace(-8, 8, 9), np.linspace(0, 8, 5))
    pixels = (256, 96) if face == "top" else (72, 256)
    spec = DicSpec(face, *FACES[face], {"pixels": pixels, "mm_per_px": 0.1, "noise": 0.005, "blur": 0.5,
                                        "supersample": 2}, {"size": 4.0, "seed": 3},
                   {"subset": subset, "step": 6, "strain_window": 5}, metrics)
    return record(build_view(spec, mesh), [np.zeros((mesh.nvertices, 3))], metrics)


@pytest.fixture(scope="module")
def by_subset():
    return {h: _record(h) for h in (15, 31)}


@pytest.mark.parametrize("subset", [15, 31])
def test_the_spatial_resolution_is_the_subsets(by_subset, subset):
    """Measured on the camera's images, SR_u is the affine subset's closed form (≈ 3.99 h) and
    SR_ε that of the subset and strain window (measured: 60.0 / 59.8 and 106.3 / 106.1 px for
    h = 15; 123.2 / 123.7 and 150.6 / 151.3 px for h = 31)."""
    r = by_subset[subset].resolution
    assert r["along"] == "x" and r["component"] == "v"
    assert r["displacement_px"] == pytest.approx(r["theory"]["displacement_px"], rel=0.03)
    assert r["strain_px"] == pytest.approx(r["theory"]["strain_px"], rel=0.05)
    assert 3.8 < r["displacement_px"] / subset < 4.2
    assert r["displacement_mm"] == pytest.approx(0.1 * r["displacement_px"])


def test_a_larger_subset_resolves_coarser_and_is_less_noisy(by_subset):
    """Doubling the subset doubles SR_u and lowers the noise floor; the MEI, their product, moves
    far less than either (measured: SR_u × 2.05, σ_v × 0.41, MEI_u × 0.83)."""
    small, large = by_subset[15], by_subset[31]
    sr = large.resolution["displacement_px"] / small.resolution["displacement_px"]
    assert 1.8 < sr < 2.3
    assert large.resolution["strain_px"] > 1.2 * small.resolution["strain_px"]
    noise = large.noise["sigma_v_px"] / small.noise["sigma_v_px"]
    assert noise < 0.7
    assert large.noise["sigma_exy_microstrain"] < 0.7 * small.noise["sigma_exy_microstrain"]
    mei = large.resolution["mei"]["displacement_px2"] / small.resolution["mei"]["displacement_px2"]
    assert abs(np.log(mei)) < 0.5 * min(abs(np.log(sr)), abs(np.log(noise)))
    assert mei == pytest.approx(sr * noise)


def test_a_face_taller_than_wide_is_swept_along_y():
    """The front face (x₁ = −z, x₂ = x) seen 72 × 256 px: the sinusoid runs down the image (u of y)."""
    r = _record(15, face="front").resolution
    assert r["along"] == "y" and r["component"] == "u"
    assert r["displacement_px"] == pytest.approx(r["theory"]["displacement_px"], rel=0.03)


def test_basic_metrics_skip_the_resolution(by_subset):
    from vlab.report.dic_metrics import metrics_dict, metrics_table

    basic = _record(15, "basic")
    assert basic.resolution is None
    assert basic.noise["sigma_v_px"] == by_subset[15].noise["sigma_v_px"]  # the same frames
    m = metrics_dict(basic)
    assert m["level"] == "basic" and "spatial_resolution" not in m
    assert 'metrics = "basic"' in metrics_table(m)


@pytest.mark.parametrize("compiled", [None, False])
def test_an_analytic_map_renders_like_the_fe_face_where_the_fe_is_exact(compiled):
    """irradiance_mapped through the inverse of a rigid shift is the FE rendering of the same
    shift (exact for any mesh) away from the face's edge, which the analytic map leaves in place."""
    import skfem

    from vlab.dic.camera import Camera, Speckle, irradiance, irradiance_mapped, paint
    from vlab.dic.face import face_of

    mesh = skfem.MeshHex.init_tensor(np.linspace(0, 12, 7), np.linspace(0, 6, 4), np.linspace(0, 2, 2))
    face = face_of(mesh, 2, 1)
    camera = Camera(pixels=(48, 24), mm_per_px=0.2, supersample=2)
    pattern = paint(face, camera, Speckle(size=3.0, seed=2))
    d = (0.07, -0.03)  # mm
    u = np.zeros((mesh.nvertices, 3))
    u[:, 0], u[:, 1] = d
    fe = irradiance(camera, face, pattern, u, compiled)
    mapped = irradiance_mapped(camera, face, pattern, lambda x1, x2: (x1 - d[0], x2 - d[1]), compiled)
    inner = (slice(2, -2), slice(2, -2))
    np.testing.assert_allclose(mapped[inner], fe[inner], rtol=0, atol=1e-9 * camera.levels)
    assert np.ptp(mapped[inner]) > 0.3 * camera.levels  # a speckled image, not a flat one
