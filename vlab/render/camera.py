"""A parallel camera fitted to a specimen: the view direction is the specimen's own where it has
one (vlab.geometry.specimen.View: a shear layer face-on), else fixed (front-right, above, for a
solid; straight from above for a flat sheet), and the scale and the window's aspect ratio follow the
bounding box of the points as seen along it, so the specimen fills its panel.

With screen axes r (right) and u (up) of the view direction d, the points' projected extents are
w = ptp(x·r), h = ptp(x·u) (mm); a window of W × H pixels with H/W = h/w (clamped to
[``min_aspect``, ``max_aspect``]) and VTK's parallel scale (half the window height in world units)
s = ½ max(h, w H/W) (1 + ``margin``) frames them exactly. One pixel of the render is then
2 s / H mm (``Camera.mm_per_pixel``), the same everywhere in the picture (parallel projection).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

VIEW_DIRECTION = np.array([0.55, -1.0, 0.75])  # from the front-right, above: x runs left to right


@dataclass(frozen=True)
class Camera:
    position: tuple
    focal_point: tuple
    viewup: tuple
    parallel_scale: float
    window: tuple[int, int]  # pixels (W, H) that the fit was made for
    extent: tuple[float, float] = (0.0, 0.0)  # mm (w, h): the framed points' width and height on screen

    @property
    def mm_per_pixel(self) -> float:
        """2 s / H: the length one render pixel spans (mm), parallel projection."""
        return 2.0 * self.parallel_scale / self.window[1]

    @property
    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(d, r, u): unit vector from the focal point to the eye, screen right and screen up."""
        d = np.subtract(self.position, self.focal_point)
        d = d / np.linalg.norm(d)
        u = np.asarray(self.viewup, float)
        return d, np.cross(u, d), u

    def as_dict(self) -> dict:
        return {"position": self.position, "focal_point": self.focal_point, "viewup": self.viewup,
                "parallel_scale": self.parallel_scale, "window": list(self.window),
                "mm_per_pixel": self.mm_per_pixel, "extent": list(self.extent)}


def is_flat(points: np.ndarray) -> bool:
    extent = np.ptp(points, axis=0)
    return bool(extent[2] <= 1e-12 * max(float(extent.max()), 1e-300))


def screen_axes(points: np.ndarray, view=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(d, r, u): unit view direction (from the focal point to the eye), screen right and up;
    ``view`` (direction, up) the specimen's own, up made normal to d (u = (up − (up·d) d)/|…|)."""
    if view is not None:
        d = np.asarray(view[0], float) / np.linalg.norm(view[0])
        up = np.asarray(view[1], float)
    elif is_flat(points):
        return np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    else:
        d, up = VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION), np.array([0.0, 0.0, 1.0])
    up = up - (up @ d) * d
    up /= np.linalg.norm(up)
    return d, np.cross(up, d), up


def fit_camera(points: np.ndarray, width: int = 1200, margin: float = 0.04,
               min_aspect: float = 0.22, max_aspect: float = 1.0, reserve_right: float = 0.0,
               view=None) -> Camera:
    """The camera and window (``width`` pixels wide) that frame ``points`` (n, 3) in mm, in the
    left ``1 − reserve_right`` of the window (the rest kept free for a colour bar), looking along
    ``view`` (direction, up) or the default direction."""
    d, r, u = screen_axes(points, view)
    x, y = points @ r, points @ u
    w, h = max(float(np.ptp(x)), 1e-9), max(float(np.ptp(y)), 1e-9)
    aspect = float(np.clip(h / w, min_aspect, max_aspect))
    height = max(int(round(width * aspect)), 64)
    usable = width * (1.0 - reserve_right)
    scale = 0.5 * max(h, w * height / usable) * (1.0 + margin)
    shift = reserve_right * scale * width / height  # half the reserved width, in mm: the points move left
    centre = points.mean(axis=0)
    focal = (centre + r * (0.5 * (x.min() + x.max()) - centre @ r + shift)
             + u * (0.5 * (y.min() + y.max()) - centre @ u))
    distance = 4.0 * max(w, h, float(np.ptp(points @ d)), 1e-9)
    return Camera(tuple(focal + distance * d), tuple(focal), tuple(u), scale, (width, height), (w, h))


def apply_camera(plotter, camera: Camera) -> None:
    plotter.enable_parallel_projection()
    plotter.camera.position = camera.position
    plotter.camera.focal_point = camera.focal_point
    plotter.camera.up = camera.viewup
    plotter.camera.parallel_scale = camera.parallel_scale
    plotter.camera.clipping_range = (1e-3 * camera.parallel_scale, 1e3 * camera.parallel_scale)
