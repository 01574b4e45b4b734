"""The virtual camera (vlab.dic.camera) against references nobody here wrote: vlab.dic.speckle's
exact rendering through the analytic map (no FE, no element inversion), the interpolation error
bound of the mesh, the statistics of Gaussian noise and the closed form of a blurred edge."""

from __future__ import annotations

import math

import numpy as np
import pytest
import skfem

from vlab.dic import icgn, speckle
from vlab.dic.camera import Camera, CameraError, Speckle, expose, irradiance, paint, render
from vlab.dic.correlate import Correlator, Settings
from vlab.dic.face import FaceError, face_of
from vlab.dic.inverse_map import reference_points
from vlab.geometry.block import block_mesh

SIZE = (20.0, 20.0, 2.0)  # mm; the camera looks at the top face z = 2
CENTRE = np.array([10.0, 10.0])


def _nodal(mesh, u_in_plane) -> np.ndarray:
    """(n_vertices, 3) displacement from a function of the in-plane reference coordinates (X, Y)."""
    p = mesh.p
    ux, uy = u_in_plane(p[0], p[1])
    return np.stack([ux, uy, np.zeros_like(ux)], axis=1)


def _in_pixels(pattern: speckle.Pattern, camera: Camera, face) -> speckle.Pattern:
    """The same speckle in image pixel coordinates (j, i) = ((x₁ − c₁)/p + (W−1)/2, −(x₂ − c₂)/p + (H−1)/2)."""
    (W, H), p, c = camera.pixels, camera.pitch, camera.centre_on(face)
    j = (pattern.centres[:, 0] - c[0]) / p + (W - 1) / 2
    i = -(pattern.centres[:, 1] - c[1]) / p + (H - 1) / 2
    return speckle.Pattern(np.stack([j, i], axis=1), pattern.radius / p, pattern.background, pattern.dark)


def _pixel_map(camera: Camera, face, inverse_mm):
    """An inverse map on image pixels from one on face mm coordinates."""
    (W, H), p, c = camera.pixels, camera.pitch, camera.centre_on(face)

    def inverse(j, i):
        X, Y = inverse_mm(c[0] + (j - (W - 1) / 2) * p, c[1] - (i - (H - 1) / 2) * p)
        return (X - c[0]) / p + (W - 1) / 2, -(Y - c[1]) / p + (H - 1) / 2
    return inverse


@pytest.fixture(scope="module")
def block():
    mesh = block_mesh(SIZE, 2.0, "hex")
    return mesh, face_of(mesh)


CAMERA = Camera(pixels=(160, 160), mm_per_px=0.1)  # 16 × 16 mm: the whole image on the face


def test_homogeneous_stretch_matches_the_exact_rendering_and_dic_recovers_it(block):
    """F = diag(1.01, 0.997) about the face centre: bilinear quads carry it exactly, so the image
    equals speckle.render through the analytic inverse to round-off; DIC (subset 31, step 10,
    strain window 5) on the 16-bit reference and deformed frames recovers E to ≤ 5e-5."""
    mesh, face = block
    exx, eyy = 0.01, -0.003
    u = _nodal(mesh, lambda X, Y: (exx * (X - CENTRE[0]), eyy * (Y - CENTRE[1])))
    pattern = paint(face, CAMERA, Speckle(size=4.0, density=0.5, seed=3))
    got = irradiance(CAMERA, face, pattern, u)
    inverse = _pixel_map(CAMERA, face, lambda x, y: (CENTRE[0] + (x - CENTRE[0]) / (1 + exx),
                                                     CENTRE[1] + (y - CENTRE[1]) / (1 + eyy)))
    want = speckle.render(_in_pixels(pattern, CAMERA, face), (160, 160), inverse, CAMERA.supersample)
    assert np.abs(got - want).max() <= 1e-9 * CAMERA.levels
    assert got.std() > 0.2 * CAMERA.levels  # a textured image, not a uniform one

    ref = render(CAMERA, face, pattern, np.zeros_like(u)).astype(float)
    f = Correlator(ref, Settings()).correlate(render(CAMERA, face, pattern, u).astype(float))
    assert (f.status == icgn.OK).all(), f.counts()
    assert abs(np.nanmean(f.exx) - (exx + exx ** 2 / 2)) <= 5e-5
    assert abs(np.nanmean(f.eyy) - (eyy + eyy ** 2 / 2)) <= 5e-5
    assert abs(np.nanmean(f.exy)) <= 5e-5
    assert np.allclose(f.u, exx * (f.x - 79.5), atol=0.01)
    assert np.allclose(f.v, eyy * (f.y - 79.5), atol=0.01)  # image y is down, face y up: same strain


A = 2e-3  # 1/mm: u₁ = A (X₂ − 10)², a bending-like shear up to 0.2 mm on the face


def _quadratic_inverse(x, y):
    return x - A * (y - CENTRE[1]) ** 2, y


@pytest.mark.parametrize("cell", ["hex", "tet"])
def test_quadratic_field_inverse_within_the_interpolation_error(cell):
    """u = (A (X₂ − c)², 0) on quads and triangles of side h: the FE interpolant errs by at most
    A h²/4 (a quadratic of range h in X₂), so the reference point found is within
    A h²/4 / (1 − max|∇u|) of the exact one; halving h divides the error by about 4."""
    errors = []
    for h in (2.0, 1.0):
        mesh = block_mesh(SIZE, h, cell)
        face = face_of(mesh)
        u = _nodal(mesh, lambda X, Y: (A * (Y - CENTRE[1]) ** 2, 0 * Y))
        xs = np.linspace(1.0, 19.0, 181)
        ys = np.linspace(19.0, 1.0, 173)
        PX, PY, hit = reference_points(face.X, face.X + face.in_plane(u), face.cells, xs, ys)
        assert hit.all()
        x, y = np.meshgrid(xs, ys)
        X, Y = _quadratic_inverse(x, y)
        err = np.hypot(PX - X, PY - Y).max()
        assert err <= A * h * h / 4 / (1 - 2 * A * 10.0)
        errors.append(err)
    assert errors[0] / errors[1] > 3.0


def test_quadratic_field_image_converges_to_the_exact_rendering():
    """The rendered image of the quadratic field approaches speckle.render through the analytic
    inverse as O(h²): the largest grey-level error falls by ≥ 3 when h halves."""
    errors = []
    for h in (2.0, 1.0):
        mesh = block_mesh(SIZE, h, "hex")
        face = face_of(mesh)
        u = _nodal(mesh, lambda X, Y: (A * (Y - CENTRE[1]) ** 2, 0 * Y))
        pattern = paint(face, CAMERA, Speckle(seed=5))
        got = irradiance(CAMERA, face, pattern, u)
        want = speckle.render(_in_pixels(pattern, CAMERA, face), (160, 160),
                              _pixel_map(CAMERA, face, _quadratic_inverse), CAMERA.supersample)
        errors.append(np.abs(got - want).max())
    assert errors[0] / errors[1] > 3.0
    assert errors[1] < 0.02 * CAMERA.levels


QUADRATIC = [("hex", skfem.ElementHex2), ("hex", skfem.ElementHexS2), ("tet", skfem.ElementTetP2)]


def _quadratic_face(cell, element, h, field):
    """The block's top face in an order-2 space, and the nodal displacement (n_nodes, 3) of
    ``field`` at the space's nodes."""
    mesh = block_mesh(SIZE, h, cell)
    basis = skfem.Basis(mesh, element(), intorder=2)
    P = basis.doflocs
    ux, uy = field(P[0], P[1])
    return mesh, face_of(mesh, basis=basis), np.stack([ux, uy, np.zeros_like(ux)], axis=1)


@pytest.mark.parametrize("cell, element", QUADRATIC, ids=["9-node", "8-node", "6-node"])
def test_quadratic_cells_carry_a_quadratic_field_exactly(cell, element):
    """u₁ = A (X₂ − 10)² lies in the order-2 space (Q2, serendipity and P2 alike), so the face's
    quadratic cells interpolate it exactly and the reference points found are the analytic inverse
    X₁ = x₁ − A (x₂ − 10)² to round-off, where the same space seen through its vertices only errs by
    the interpolation error A h²/4 = 2e-3 mm (h = 2 mm)."""
    h = 2.0
    mesh, face, u = _quadratic_face(cell, element, h, lambda X, Y: (A * (Y - CENTRE[1]) ** 2, 0 * Y))
    assert face.cells.shape[1] == {"ElementHex2": 9, "ElementHexS2": 8, "ElementTetP2": 6}[element.__name__]
    xs, ys = np.linspace(1.0, 19.0, 181), np.linspace(19.0, 1.0, 173)
    x, y = np.meshgrid(xs, ys)
    X, Y = _quadratic_inverse(x, y)
    PX, PY, hit = reference_points(face.X, face.X + face.in_plane(u), face.cells, xs, ys)
    assert hit.all()
    assert np.hypot(PX - X, PY - Y).max() <= 1e-12
    vertices = face_of(mesh)
    PX, PY, _ = reference_points(vertices.X, vertices.X + vertices.in_plane(u), vertices.cells, xs, ys)
    assert np.hypot(PX - X, PY - Y).max() >= 0.9 * A * h * h / 4


def test_quadratic_cells_render_the_exact_image():
    """The camera's image of u₁ = A (X₂ − 10)² on 9-node face cells (h = 2 mm) equals
    speckle.render through the analytic inverse to round-off, as the homogeneous stretch does on
    bilinear cells (on those, the same field errs by hundreds of grey levels)."""
    _, face, u = _quadratic_face("hex", skfem.ElementHex2, 2.0, lambda X, Y: (A * (Y - CENTRE[1]) ** 2, 0 * Y))
    pattern = paint(face, CAMERA, Speckle(seed=5))
    got = irradiance(CAMERA, face, pattern, u)
    want = speckle.render(_in_pixels(pattern, CAMERA, face), (160, 160),
                          _pixel_map(CAMERA, face, _quadratic_inverse), CAMERA.supersample)
    assert np.abs(got - want).max() <= 1e-9 * CAMERA.levels


@pytest.mark.parametrize("k", [3, 4, 6, 8, 9])
def test_shape_functions_are_nodal_sum_to_one_and_differentiate_right(k):
    """N_a(ξ_b) = δ_ab at the nodes, Σ_a N_a = 1 anywhere, and ∂N/∂ξ, ∂N/∂η equal central
    differences (step 1e-6) to 1e-8."""
    from vlab.dic.inverse_map import NODES, shape_functions

    nodes = {3: [[0, 0], [1, 0], [0, 1]], 6: [[0, 0], [1, 0], [0, 1], [0.5, 0], [0.5, 0.5], [0, 0.5]]}
    P = np.array(nodes.get(k, NODES[:k]), float)
    assert np.allclose(shape_functions(k, P[:, 0], P[:, 1])[0], np.eye(k), rtol=0, atol=1e-15)
    xi, eta = np.random.default_rng(k).uniform(-0.3, 0.4, (2, 7))
    N, dxi, deta = shape_functions(k, xi, eta)
    assert np.allclose(N.sum(axis=0), 1.0, rtol=0, atol=1e-14)
    h = 1e-6
    assert np.allclose(dxi, (shape_functions(k, xi + h, eta)[0] - shape_functions(k, xi - h, eta)[0]) / (2 * h),
                       rtol=0, atol=1e-8)
    assert np.allclose(deta, (shape_functions(k, xi, eta + h)[0] - shape_functions(k, xi, eta - h)[0]) / (2 * h),
                       rtol=0, atol=1e-8)


def test_face_of_a_space_the_camera_cannot_take_is_named():
    mesh = block_mesh(SIZE, 2.0, "tet")
    with pytest.raises(FaceError, match="ElementTetP0"):
        face_of(mesh, basis=skfem.Basis(mesh, skfem.ElementTetP0(), intorder=1))


def test_noise_of_two_frames_differs_by_sqrt2_sigma(block):
    """Two frames of the same state carry independent sensor noise of std σ: their difference has
    std √2 σ (within 3 % on 160² pixels); the same frame number repeats exactly."""
    mesh, face = block
    camera = Camera(pixels=(160, 160), mm_per_px=0.1, noise=0.01, seed=7)
    pattern = paint(face, camera, Speckle())
    u = np.zeros((mesh.nvertices, 3))
    a, b = (render(camera, face, pattern, u, frame=k).astype(float) for k in (1, 2))
    sigma = 0.01 * camera.levels
    assert abs((a - b).std() / (math.sqrt(2) * sigma) - 1) < 0.03
    assert abs((a - b).mean()) < 0.05 * sigma
    assert np.array_equal(a, render(camera, face, pattern, u, frame=1))


def test_blur_turns_an_edge_into_the_gaussian_error_function():
    """A step of height S blurred by a Gaussian of σ px is S Φ((x − x₀)/σ); exposed at 16 bits it
    matches to within a grey level plus the midpoint-rule error of the kernel sampled on pixels,
    h²/24 · max|g'| · S = S / (24 σ² √(2π e)) (h = 1 px), 0.25 % of S at σ = 2."""
    camera = Camera(pixels=(64, 64), mm_per_px=0.1, blur=2.0)
    step = 40000.0
    image = np.zeros((64, 64))
    image[:, 32:] = step  # the edge at x₀ = 31.5 px
    got = expose(camera, image).astype(float)
    x = np.arange(64)
    want = step * 0.5 * (1 + np.vectorize(math.erf)((x - 31.5) / (2.0 * math.sqrt(2))))
    bound = 1 + step / (24 * 2.0 ** 2 * math.sqrt(2 * math.pi * math.e))
    assert np.abs(got[32] - want).max() <= bound
    assert np.abs(got[32] - want).max() > 0.5 * bound  # the bound is the error's size, not a loose cap


def test_camera_that_cannot_see_the_face_is_refused(block):
    _, face = block
    camera = Camera(pixels=(100, 100), mm_per_px=0.05, centre=(40.0, 10.0))  # 5 mm wide, 30 mm off
    with pytest.raises(CameraError, match="cannot see the face") as err:
        paint(face, camera, Speckle())
    assert err.value.field == "centre" and "x₁ 0…20" in str(err.value)


@pytest.mark.parametrize("change, name", [
    (dict(bit_depth=12), "bit_depth"), (dict(pixels=(0, 10)), "pixels"),
    (dict(field_of_view=10.0), "mm_per_px"), (dict(mm_per_px=-1.0), "mm_per_px"),
    (dict(noise=-0.1), "noise"), (dict(supersample=0), "supersample"), (dict(pixels=512), "pixels"),
    (dict(noise="1%"), "noise"), (dict(blur=float("nan")), "blur"), (dict(centre=(1.0,)), "centre"),
    (dict(mm_per_px=None, field_of_view=0.0), "field_of_view")])
def test_bad_camera_settings_named(change, name):
    with pytest.raises(CameraError) as err:
        Camera(**{"mm_per_px": 0.1, **change}).check()
    assert err.value.field == name and str(err.value).startswith(f"camera.{name}")


def test_bad_speckle_and_face_named(block):
    mesh, _ = block
    with pytest.raises(CameraError, match="speckle.density"):
        Speckle(density=0.0).check()
    with pytest.raises(CameraError, match="speckle.size"):
        Speckle(size="4").check()
    with pytest.raises(FaceError, match="axis must be"):
        face_of(mesh, axis=3)


def test_compiled_camera_matches_its_numpy_twin():
    """The numba kernels (vlab.dic.camera_kernel) and the numpy loops do the same arithmetic:
    the same pixels on the face, reference points and grey levels to round-off, on quads and
    triangles under a non-homogeneous field, with the face edge in view."""
    pytest.importorskip("numba")
    for cell in ("hex", "tet"):
        mesh = block_mesh(SIZE, 2.0, cell)
        face = face_of(mesh)
        u = _nodal(mesh, lambda X, Y: (A * (Y - CENTRE[1]) ** 2, 1e-3 * X * Y))
        camera = Camera(pixels=(96, 80), mm_per_px=0.25, supersample=2, centre=(18.0, 3.0))
        x1, x2 = camera.axes(face)
        x = face.X + face.in_plane(u)
        a = reference_points(face.X, x, face.cells, x1, x2, compiled=True)
        b = reference_points(face.X, x, face.cells, x1, x2, compiled=False)
        assert np.array_equal(a[2], b[2]) and 0.2 < a[2].mean() < 0.8  # part of the view is background
        assert np.allclose(a[0], b[0], rtol=0, atol=1e-11, equal_nan=True)
        assert np.allclose(a[1], b[1], rtol=0, atol=1e-11, equal_nan=True)
        pattern = paint(face, camera, Speckle(seed=2))
        assert np.allclose(irradiance(camera, face, pattern, u, compiled=True),
                           irradiance(camera, face, pattern, u, compiled=False), rtol=0, atol=1e-8)


@pytest.mark.parametrize("cell, element", QUADRATIC, ids=["9-node", "8-node", "6-node"])
def test_compiled_quadratic_cells_match_their_numpy_twin(cell, element):
    """The same on quadratic face cells made curved by a field outside the space (a sine), with the
    face's edge in view: the same sub-samples on the face, reference points to round-off."""
    pytest.importorskip("numba")
    _, face, u = _quadratic_face(cell, element, 2.0, lambda X, Y: (A * (Y - CENTRE[1]) ** 2 + 0.05 * np.sin(Y),
                                                                   1e-3 * X * Y + 0.05 * np.sin(X)))
    camera = Camera(pixels=(96, 80), mm_per_px=0.25, supersample=2, centre=(18.0, 3.0))
    x1, x2 = camera.axes(face)
    x = face.X + face.in_plane(u)
    a = reference_points(face.X, x, face.cells, x1, x2, compiled=True)
    b = reference_points(face.X, x, face.cells, x1, x2, compiled=False)
    assert np.array_equal(a[2], b[2]) and 0.2 < a[2].mean() < 0.8
    assert np.allclose(a[0], b[0], rtol=0, atol=1e-11, equal_nan=True)
    assert np.allclose(a[1], b[1], rtol=0, atol=1e-11, equal_nan=True)


def test_dogbone_face_sub_samples_are_those_inside_its_cells_and_the_rest_is_background():
    """An ASTM D412 C dogbone's top face (fillets as straight-sided quads), at rest: the sub-samples
    found on the face are exactly those matplotlib's point-in-polygon test puts inside one of its
    cells, and every pixel wholly off it is the background grey exactly."""
    from matplotlib.path import Path

    from vlab.geometry.dogbone import DogboneDimensions, dogbone_mesh
    from vlab.geometry.standards import standard_dimensions

    mesh = dogbone_mesh(DogboneDimensions(**standard_dimensions("ASTM D412 C")), 2.0, "hex")
    face = face_of(mesh)
    camera = Camera(pixels=(480, 120), mm_per_px=0.25, supersample=2)
    x1, x2 = camera.axes(face)
    _, _, hit = reference_points(face.X, face.X, face.cells, x1, x2)
    gx, gy = np.meshgrid(x1, x2)
    points = np.stack([gx.ravel(), gy.ravel()], axis=1)
    inside = np.zeros(len(points), bool)
    for cell in face.cells:
        inside |= Path(face.X[cell]).contains_points(points)
    assert np.array_equal(hit.ravel(), inside) and 0.3 < inside.mean() < 0.7
    image = irradiance(camera, face, paint(face, camera, Speckle()), np.zeros((mesh.nvertices, 3)))
    off = ~hit.reshape(120, 2, 480, 2).any(axis=(1, 3))
    assert off.sum() > 0.3 * off.size
    assert np.all(image[off] == camera.background * camera.levels)
