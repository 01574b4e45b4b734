"""A scene's ``[instruments.dic]`` in a run: the camera's images of every recorded level and their DIC.

The camera looks at the specimen's face (vlab.dic.face.face_of(mesh, axis, side)); the speckle
is painted on the reference face once (vlab.dic.camera.paint); frame 0 is the unloaded reference
and frame k the k-th converged level, rendered from the nodal displacement of the mesh vertices
(vlab.dic.camera.render: each frame a fresh draw of the sensor noise). Each level is correlated
against the reference, seeded by the previous level's field (vlab.dic.correlate.Correlator), over
the region of interest: the subsets that lie wholly on the reference face (region_of_interest).

The static pair gives the noise floor (DIC Challenge 2.0, vlab.dic.metrics.static_noise): the
reference rendered twice more with fresh noise (frames NOISE_FRAMES) and correlated, so σ_u, σ_v
(px) and σ_Exx, σ_Eyy (µε) are those of this camera, pattern and settings on this face; the face
rigidly shifted by half a pixel along e₁ and e₂ and correlated against the first of the pair gives
the sub-pixel translation bias (translation_bias). With metrics = "full" (the default), the
spatial resolution of the same camera, pattern and settings and the Metrological Efficiency
Indicator (vlab.dic.resolution): sinusoidal fields rendered exactly and correlated against the
reference, a few more images than the levels (each about a level's rendering and correlation).

Pixel ↔ face convention (vlab.dic.camera): pixel (row i, column j) of a W × H image is centred on
the face point x₁ = c₁ + (j − (W − 1)/2) p, x₂ = c₂ − (i − (H − 1)/2) p (mm), with the face's
in-plane axes e₁, e₂ given as (mesh axis, sign) and the face plane X_axis = plane.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from vlab.dic.camera import Camera, CameraError, Speckle, check_view, paint, render
from vlab.dic.correlate import Correlator, Field, Settings
from vlab.dic.face import Face, FaceError, face_of
from vlab.dic.inverse_map import reference_points

NOISE_FRAMES = (1_000_001, 1_000_002)  # frame indices of the static pair (never a level's)
TRANSLATION_PX = 0.5  # the rigid sub-pixel shift of the bias check: mid-pixel, where interpolation bias peaks


@dataclass(frozen=True)
class View:
    """What the camera looks at: the built Camera, Speckle and Settings, the face and its plane
    (the mesh coordinate X_axis of the face, mm)."""

    camera: Camera
    speckle: Speckle
    settings: Settings
    face: Face
    axis: int
    side: int
    name: str
    plane: float

    def face_mm(self, x_px: np.ndarray, y_px: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Face coordinates (x₁, x₂) in mm of image points (x right, y down, px)."""
        (W, H), p = self.camera.pixels, self.camera.pitch
        c = self.camera.centre_on(self.face)
        return c[0] + (np.asarray(x_px, float) - (W - 1) / 2) * p, c[1] - (np.asarray(y_px, float) - (H - 1) / 2) * p

    def mesh_points(self, x1: np.ndarray, x2: np.ndarray) -> np.ndarray:
        """(3, n) mesh coordinates (mm) of face points (x₁, x₂): X[a_k] = s_k x_k, X[axis] = plane."""
        out = np.empty((3, np.size(x1)))
        out[self.axis] = self.plane
        for (a, s), x in zip(self.face.axes, (x1, x2)):
            out[a] = s * np.ravel(x)
        return out

    def as_dict(self) -> dict:
        """dic.json's "camera": enough for another program to map pixels to specimen coordinates."""
        cam = self.camera
        return {"pixels": list(cam.pixels), "mm_per_px": cam.pitch, "centre_mm": [float(c) for c in cam.centre_on(self.face)],
                "bit_depth": cam.bit_depth, "noise": cam.noise, "blur": cam.blur, "supersample": cam.supersample,
                "seed": cam.seed, "background": cam.background,
                "face": {"name": self.name, "axis": "xyz"[self.axis], "side": self.side, "plane_mm": self.plane,
                         "e1": _axis_name(self.face.axes[0]), "e2": _axis_name(self.face.axes[1])},
                "speckle": {"size_px": self.speckle.size, "density": self.speckle.density, "seed": self.speckle.seed},
                "convention": "pixel (row i, column j) is centred on the face point x1 = c1 + (j - (W - 1)/2) p, "
                              "x2 = c2 - (i - (H - 1)/2) p (mm; p = mm_per_px, c = centre_mm); the specimen point "
                              "is X[e1 axis] = sign * x1, X[e2 axis] = sign * x2, X[face axis] = plane_mm; "
                              "CSV x_px = j, y_px = i"}


def _axis_name(axis_sign: tuple[int, int]) -> str:
    a, s = axis_sign
    return ("+" if s > 0 else "-") + "xyz"[a]


def build_view(spec, mesh) -> View:
    """The View of a scene's DicSpec on the specimen mesh; CameraError/FaceError (naming the
    setting) if a setting is out of range, the face is missing or the camera cannot see it."""
    camera, speckle = Camera(**spec.camera), Speckle(**spec.speckle)
    settings = Settings(**spec.settings)
    camera.check()
    speckle.check()
    face = face_of(mesh, spec.axis, spec.side)
    check_view(camera, face)
    coords = mesh.p[spec.axis]
    return View(camera, speckle, settings, face, spec.axis, spec.side, spec.face,
                float(coords.max() if spec.side > 0 else coords.min()))


def region_of_interest(view: View) -> np.ndarray:
    """(H, W) bool: the pixels whose subset and its 2-px gradient stencil ((subset + 4)² px about
    them, as vlab.dic.correlate.grid keeps from the image border) lie on the reference face, so no
    correlated subset straddles the specimen's edge (the DIC user's region of interest, drawn from
    the geometry the camera knows). Without the stencil's 2 px, the row of subsets whose last
    pixel is cut by the edge read v 0.035 px off (22 % of it) at 5e-4 transverse strain."""
    from scipy.ndimage import binary_erosion

    W, H = view.camera.pixels
    x1, x2 = view.face_mm(np.arange(W), np.arange(H))
    face = view.face
    _, _, on = reference_points(face.X, face.X, face.cells, x1, x2)
    n = view.settings.subset + 4
    return binary_erosion(on, structure=np.ones((n, n), bool), border_value=0)


def translation_bias(view: View, pattern, static: Correlator, n_vertices: int, shift: float = TRANSLATION_PX) -> dict:
    """Bias and scatter (px) of a rigid in-plane translation of the face by ``shift`` px along both
    e₁ and e₂ (DIC Challenge 2.0): the image moves by (u, v) = (+shift, −shift) px (y runs down);
    bias = mean measured − true over the converged subsets, std their standard deviation."""
    from vlab.dic import icgn

    u = np.zeros((n_vertices, 3))
    for a, s in view.face.axes:
        u[:, a] = s * shift * view.camera.pitch
    moved = render(view.camera, view.face, pattern, u, frame=NOISE_FRAMES[-1] + 1)
    f = static.correlate(moved.astype(float))
    ok = f.status == icgn.OK
    if not ok.any():
        return {"shift_px": shift, "bias_u_px": None, "bias_v_px": None, "std_u_px": None, "std_v_px": None}
    eu, ev = f.u[ok] - shift, f.v[ok] + shift
    return {"shift_px": shift, "bias_u_px": float(eu.mean()), "bias_v_px": float(ev.mean()),
            "std_u_px": float(eu.std()), "std_v_px": float(ev.std())}


@dataclass
class Record:
    """The camera's frames (frame 0 the reference), the DIC field of every deformed frame, the
    noise floor and translation bias (``noise``) and, with metrics = "full", the spatial
    resolution and MEI (``resolution``, vlab.dic.resolution; None with "basic")."""

    view: View
    images: list[np.ndarray]
    fields: list[Field]
    noise: dict
    timing: dict = field(default_factory=dict)
    resolution: dict | None = None


def record(view: View, displacements: list[np.ndarray], metrics: str = "full") -> Record:
    """Render every frame of ``displacements`` ((n_vertices, 3) mm each, frame 0 = 0), correlate
    each deformed frame against frame 0 seeded by the previous field, and measure the noise floor,
    the translation bias and (``metrics`` = "full") the spatial resolution and MEI."""
    t0 = time.perf_counter()
    pattern = paint(view.face, view.camera, view.speckle)
    images = [render(view.camera, view.face, pattern, u, frame=k) for k, u in enumerate(displacements)]
    t1 = time.perf_counter()
    roi = region_of_interest(view)
    correlator = Correlator(images[0].astype(float), view.settings, roi=roi)
    fields, previous = [], None
    for image in images[1:]:
        previous = correlator.correlate(image.astype(float), guess=previous)
        fields.append(previous)
    t2 = time.perf_counter()
    noise = noise_floor(view, pattern, roi, displacements[0])
    t3 = time.perf_counter()
    resolution = None
    if metrics == "full":
        from vlab.dic.metrics import mei
        from vlab.dic.resolution import spatial_resolution

        resolution = spatial_resolution(view, pattern, correlator)
        resolution["mei"] = mei(noise, resolution)
    timing = {"render_s": t1 - t0, "correlate_s": t2 - t1, "noise_floor_s": t3 - t2,
              "resolution_s": time.perf_counter() - t3, "levels": len(fields)}
    return Record(view, images, fields, noise, timing, resolution)


def noise_floor(view: View, pattern, roi: np.ndarray, unloaded: np.ndarray) -> dict:
    """The static pair's noise (vlab.dic.metrics.static_noise; σ_u also in mm) and the 0.5 px
    translation bias, on the reference rendered twice more with fresh noise (NOISE_FRAMES)."""
    from vlab.dic.metrics import static_noise

    still = [render(view.camera, view.face, pattern, unloaded, frame=k) for k in NOISE_FRAMES]
    static = Correlator(still[0].astype(float), view.settings, roi=roi)
    noise = static_noise(static.correlate(still[1].astype(float))) | {"frames": list(NOISE_FRAMES)}
    if noise["sigma_u_px"] is not None:
        noise["sigma_u_mm"] = 0.5 * (noise["sigma_u_px"] + noise["sigma_v_px"]) * view.camera.pitch
    noise["translation"] = translation_bias(view, pattern, static, len(unloaded))
    return noise


__all__ = ["View", "Record", "build_view", "record", "CameraError", "FaceError", "NOISE_FRAMES"]
