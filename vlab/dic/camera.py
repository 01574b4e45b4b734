"""The virtual camera: images of a specimen's speckled face rendered from the FE displacement.

The camera looks along the face's inward normal (vlab.dic.face: in-plane axes e₁ to the right, e₂
up). Pixel (row i, column j) of a W × H image is centred on the face point (mm)

    x₁ = c₁ + (j − (W − 1)/2) p,   x₂ = c₂ − (i − (H − 1)/2) p

with p the pixel pitch on the specimen (mm/px, or field of view / W) and c the point at the image
centre (default: the centre of the reference face). The speckle is painted on the reference face
(vlab.dic.speckle's pattern, its Gaussians scaled from reference pixels to mm). A level is
rendered by mapping each of a pixel's s × s sub-samples x back to its reference point X = φ⁻¹(x)
through the FE interpolation (vlab.dic.inverse_map), evaluating the speckle there, and averaging
(the pixel integrates the light on it), so the rendering adds no image interpolation; sub-samples
off the specimen see the background. The exposure then blurs the irradiance with a Gaussian of
σ_b px (the optics), adds Gaussian grey-level noise of standard deviation σ_n · (2^bits − 1) (the
sensor, a fresh draw per frame from the camera's seed) and rounds to the bit depth.

How a scene's ``[instruments.dic]`` uses it: build a Camera and a Speckle from the table, take
``face = face_of(specimen.mesh, axis, side)``, ``pattern = paint(face, camera, speckle)`` once,
then for frame k of the Snapshot ``image = render(camera, face, pattern,
snapshot.displacement[k], frame=k)`` (frame 0, u = 0, is the reference image), and pass the images
to vlab.dic.correlate.Correlator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vlab.dic import speckle
from vlab.dic.camera_kernel import compiled_kernels
from vlab.dic.face import Face
from vlab.dic.inverse_map import reference_points


class CameraError(ValueError):
    """A camera or speckle setting vlab cannot use, or a camera that cannot see the face (exit 2);
    ``field``: the name of the bad setting."""

    def __init__(self, message: str, field: str | None = None):
        super().__init__(message)
        self.field = field


def _integer(value) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def _within(value, lo: float, hi: float) -> bool:
    """A finite real number in [lo, hi] (bools and strings are not numbers here)."""
    return (isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
            and math.isfinite(value) and lo <= value <= hi)


@dataclass(frozen=True)
class Camera:
    """pixels: (W, H); mm_per_px or field_of_view (the width W p, mm): exactly one; bit_depth 8 or
    16; noise: grey-level noise std as a share of full scale; blur: Gaussian σ (px, 0 = sharp);
    supersample: s (s² sub-samples a pixel); seed of the noise; centre: face point (mm) at the
    image centre (None: the reference face's centre); background: grey off the specimen (share of
    full scale)."""

    pixels: tuple[int, int] = (1024, 1024)
    mm_per_px: float | None = None
    field_of_view: float | None = None
    bit_depth: int = 16
    noise: float = 0.0
    blur: float = 0.0
    supersample: int = 3
    seed: int = 0
    centre: tuple[float, float] | None = None
    background: float = 0.02

    @property
    def pitch(self) -> float:
        """p, mm per pixel on the specimen."""
        return self.mm_per_px if self.mm_per_px is not None else self.field_of_view / self.pixels[0]

    @property
    def levels(self) -> float:
        """Full scale, 2^bits − 1 grey levels."""
        return float(2 ** self.bit_depth - 1)

    def check(self) -> None:
        def need(ok, name, allowed):
            if not ok:
                raise CameraError(f"camera.{name} = {getattr(self, name)!r}: {allowed}", name)

        need(isinstance(self.pixels, (tuple, list)) and len(self.pixels) == 2
             and all(_integer(n) and 16 <= n <= 16384 for n in self.pixels),
             "pixels", "must be (width, height), integers in [16, 16384]")
        need((self.mm_per_px is None) != (self.field_of_view is None), "mm_per_px",
             "give exactly one of mm_per_px and field_of_view")
        scale = "mm_per_px" if self.mm_per_px is not None else "field_of_view"
        need(_within(getattr(self, scale), 0, math.inf) and getattr(self, scale) > 0, scale,
             "must be a positive length (mm)")
        need(self.bit_depth in (8, 16), "bit_depth", "must be 8 or 16")
        need(_within(self.noise, 0, 0.5), "noise", "must be in [0, 0.5] (share of full scale)")
        need(_within(self.blur, 0, 50), "blur", "must be in [0, 50] px")
        need(_integer(self.supersample) and 1 <= self.supersample <= 8, "supersample",
             "must be an integer in [1, 8]")
        need(_within(self.background, 0, 1), "background", "must be in [0, 1] (share of full scale)")
        need(_integer(self.seed), "seed", "must be an integer")
        need(self.centre is None or (isinstance(self.centre, (tuple, list)) and len(self.centre) == 2
                                     and all(_within(c, -math.inf, math.inf) for c in self.centre)),
             "centre", "must be (x₁, x₂) in mm on the face, or None (the face's centre)")

    def centre_on(self, face: Face) -> np.ndarray:
        lo, hi = face.bounds
        return (lo + hi) / 2 if self.centre is None else np.asarray(self.centre, float)

    def axes(self, face: Face) -> tuple[np.ndarray, np.ndarray]:
        """Face coordinates (mm) of the sub-sample grid: x₁ of each sub-column (ascending), x₂ of
        each sub-row (descending: rows go down the image)."""
        (W, H), s, p = self.pixels, self.supersample, self.pitch
        c = self.centre_on(face)
        sub = (np.arange(s) + 0.5) / s - 0.5
        cols = (np.arange(W)[:, None] + sub).ravel() - (W - 1) / 2
        rows = (np.arange(H)[:, None] + sub).ravel() - (H - 1) / 2
        return c[0] + cols * p, c[1] - rows * p


@dataclass(frozen=True)
class Speckle:
    """size: speckle diameter (px of the reference image); density: share of the face covered by
    speckle discs, in (0, 1]; seed of the speckle positions."""

    size: float = 4.0
    density: float = 0.5
    seed: int = 0

    def check(self) -> None:
        if not _within(self.size, 1.0, 100.0):
            raise CameraError(f"speckle.size = {self.size!r}: must be in [1, 100] px", "size")
        if not (_within(self.density, 0, 1) and self.density > 0):
            raise CameraError(f"speckle.density = {self.density!r}: must be in (0, 1]", "density")
        if not _integer(self.seed):
            raise CameraError(f"speckle.seed = {self.seed!r}: must be an integer", "seed")


def check_view(camera: Camera, face: Face) -> None:
    """CameraError unless the field of view overlaps the reference face (a camera that sees
    none of the face has nothing to correlate)."""
    x1, x2 = camera.axes(face)
    lo, hi = face.bounds
    if x1[-1] <= lo[0] or x1[0] >= hi[0] or x2[0] <= lo[1] or x2[-1] >= hi[1]:
        raise CameraError(
            f"camera.centre = {[round(float(c), 6) for c in camera.centre_on(face)]} mm with a field of view of "
            f"{x1[-1] - x1[0]:.4g} × {x2[0] - x2[-1]:.4g} mm (x₁ {x1[0]:.4g}…{x1[-1]:.4g}, x₂ "
            f"{x2[-1]:.4g}…{x2[0]:.4g}) cannot see the face (x₁ {lo[0]:.4g}…{hi[0]:.4g}, "
            f"x₂ {lo[1]:.4g}…{hi[1]:.4g} mm): move the centre into the face", "centre")


def paint(face: Face, camera: Camera, pattern: Speckle) -> speckle.Pattern:
    """The speckle on the reference face, in mm: vlab.dic.speckle.make_pattern over the face's
    bounding box in reference pixels (plus two speckle sizes of margin), centres and radius × p."""
    camera.check()
    pattern.check()
    check_view(camera, face)
    lo, hi = face.bounds
    p = camera.pitch
    shape = (int(math.ceil((hi[1] - lo[1]) / p)), int(math.ceil((hi[0] - lo[0]) / p)))
    px = speckle.make_pattern(shape, pattern.size, pattern.density, pattern.seed, camera.levels,
                              margin=2 * pattern.size)
    return speckle.Pattern(lo + px.centres * p, px.radius * p, px.background, px.dark)


def irradiance(camera: Camera, face: Face, pattern: speckle.Pattern, u: np.ndarray,
               compiled: bool | None = None) -> np.ndarray:
    """The sharp noiseless image (H, W) in grey levels (float) of the face displaced by ``u`` (the
    mesh's nodal displacement (n_vertices, 3), mm): each pixel the mean over its s × s
    sub-samples of I(φ⁻¹(x)), I the speckle on the face and the background off it.
    ``compiled``: None uses the numba kernels when available, False their numpy twins."""
    x1, x2 = camera.axes(face)
    x = face.X + face.in_plane(u)
    PX, PY, hit = reference_points(face.X, x, face.cells, x1, x2, compiled)
    return _speckle_means(camera, pattern, PX, PY, hit, compiled)


def irradiance_mapped(camera: Camera, face: Face, pattern: speckle.Pattern, inverse,
                      compiled: bool | None = None) -> np.ndarray:
    """The sharp noiseless image (H, W) of the face moved by an analytic in-plane field whose
    inverse ``inverse(x₁, x₂) -> (X₁, X₂)`` (face mm, arrays of the sub-sample grid) is known
    exactly: each pixel the mean over its s × s sub-samples of I(X), so a field finer than the
    FE mesh (a sinusoid of a few subsets' period) is rendered without the FE interpolation.
    Sub-samples off the reference face see the background: the face's outline is not moved
    (the field must be small near the edge, where no subset of the region of interest looks)."""
    x1, x2 = camera.axes(face)
    _, _, hit = reference_points(face.X, face.X, face.cells, x1, x2, compiled)
    PX, PY = inverse(*np.meshgrid(x1, x2))
    PX, PY = np.where(hit, PX, np.nan), np.where(hit, PY, np.nan)
    return _speckle_means(camera, pattern, np.ascontiguousarray(PX, float), np.ascontiguousarray(PY, float),
                          hit, compiled)


def _speckle_means(camera: Camera, pattern: speckle.Pattern, PX: np.ndarray, PY: np.ndarray, hit: np.ndarray,
                   compiled: bool | None) -> np.ndarray:
    """Each pixel's mean over its s × s sub-samples of the speckle at (PX, PY) where ``hit``, of
    the background elsewhere (the numba kernel when available, else its numpy twin)."""
    (W, H), s = camera.pixels, camera.supersample
    background = camera.background * camera.levels
    kernels = compiled_kernels() if compiled is not False else None
    if kernels is None:
        return _pixel_means_numpy(pattern, PX, PY, hit, background, s)
    from vlab import jit

    t = speckle.cell_table(pattern)
    out = np.empty((H, W))
    jit.call(kernels.pixel_means, t.table, t.origin[0], t.origin[1], t.cell, t.ncx, t.ncy,
             1.0 / pattern.radius ** 2, speckle.CUTOFF ** 2, pattern.background, pattern.dark, speckle.KAPPA,
             PX, PY, hit, background, s, out)
    return out


def _pixel_means_numpy(pattern: speckle.Pattern, PX: np.ndarray, PY: np.ndarray, hit: np.ndarray,
                       background: float, s: int) -> np.ndarray:
    """The mean over each pixel's s × s sub-samples of I(PX, PY) on the face, the background off it."""
    grey = np.full(PX.shape, background)
    grey[hit] = speckle.intensity(pattern, PX[hit], PY[hit])
    rows, cols = PX.shape
    return grey.reshape(rows // s, s, cols // s, s).mean(axis=(1, 3))


def expose(camera: Camera, image: np.ndarray, frame: int = 0) -> np.ndarray:
    """The recorded image: the irradiance blurred by a Gaussian of σ = camera.blur px (optics),
    plus normal noise of std camera.noise · levels (sensor; generator seeded by (seed, frame)),
    rounded and clipped to [0, 2^bits − 1]; uint8 or uint16."""
    if camera.blur > 0:
        from scipy.ndimage import gaussian_filter

        image = gaussian_filter(image, camera.blur, mode="nearest")
    if camera.noise > 0:
        rng = np.random.default_rng([camera.seed, frame])
        image = image + rng.normal(0.0, camera.noise * camera.levels, image.shape)
    dtype = np.uint8 if camera.bit_depth == 8 else np.uint16
    return np.clip(np.rint(image), 0, camera.levels).astype(dtype)


def render(camera: Camera, face: Face, pattern: speckle.Pattern, u: np.ndarray, frame: int = 0) -> np.ndarray:
    """One recorded frame (H, W) of the face displaced by ``u``: expose(irradiance(...))."""
    camera.check()
    return expose(camera, irradiance(camera, face, pattern, u), frame)
