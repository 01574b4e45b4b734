"""Cruciform specimen for biaxial tests: outline, validation, structured mesh, grips and gauge marks.

Outline (mm), centred on the origin, thickness 0 ≤ z ≤ h: a central square of side w (the arm
width) with four arms of width w and length ℓ (measured from the central square, so an arm ends at
|x| = X = w/2 + ℓ). The re-entrant corners between neighbouring arms are rounded by a fillet of
radius r tangent to both arm edges: centre (w/2 + r, w/2 + r), so along the +x arm the half-width is
    hw(x) = w/2 + r − √(r² − (w/2 + r − x)²)     for w/2 ≤ x ≤ w/2 + r,     w/2 beyond.
The fillet meets the diagonal x = y at c = w/2 + r (1 − 1/√2). Optional slits (the ISO 16842 design)
cut each arm into n + 1 fingers of equal width (w − n s)/(n + 1): slits of width s, open at the arm
end, running ``slit_length`` inwards; they stop the arms from carrying load across each other, so
more of the load passes through the gauge region. Optionally the centre is thinned from both faces
to ``gauge_thickness`` h_g < h (so failure, and the strain, concentrate there): with the Chebyshev
distance s = max(|x|, |y|) − g/2 from the gauge region, the thickness is
    t(s) = h_g                                            for s ≤ 0,
    t(s) = h_g + (h − h_g) (1 − cos(π s / ℓ_t)) / 2       for 0 ≤ s ≤ ℓ_t (``thinning_length``),
    t(s) = h                                              beyond,
a smooth (zero-slope) ramp that must end inside the central square, g + 2 ℓ_t ≤ w.
The central gauge region is the square of side g = ``gauge_region``
(≤ w) where the extensometers sit and the centre stress is averaged.

Mesh (vlab's own structured mesher): in the quadrant x, y ≥ 0, a lattice on the square
[0, w/2]² and, for the +x arm, a mapped block x ∈ [w/2, X], y = η · top(x), η ∈ [0, 1], with
top(x) = min(x, hw(x)): the arm's half-width, cut by the diagonal where the fillet bulges past it.
The +y arm is the mirror image across x = y, so the quadrant is symmetric under x ↔ y; it is
extruded over the upper half of the thickness and mirrored across y = 0, x = 0 and z = h/2
(geometry/lattice.py; the Kuhn tet split keeps the x ↔ y symmetry), so an equibiaxial test reads
the same on both axes to round-off. Mesh planes sit at the gauge region edge, the diagonal/fillet
junction, the end of the fillet, the slit edges and the grip edges.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vlab import fields
from vlab.fields import SceneError

from vlab.geometry.dogbone import GeometryError
from vlab.geometry.counts import CUT, MeshCount, div
from vlab.geometry.shape import Shape
from vlab.geometry.lattice import Lattice, divisions, symmetric_mesh
from vlab.geometry.specimen import GaugeMarks, Grip, Specimen
from vlab.geometry.symmetry import mirrored_planes

CRUCIFORM_KEYS = ("arm_width", "arm_length", "gauge_region", "fillet_radius", "thickness", "grip_length",
                  "slit_count", "slit_width", "slit_length", "gauge_thickness", "thinning_length")


@dataclass(frozen=True)
class CruciformDimensions:
    """A cruciform's dimensions, mm (module docstring); ``slit_count`` = 0: no slits."""

    arm_width: float
    arm_length: float
    gauge_region: float
    fillet_radius: float
    thickness: float
    grip_length: float
    slit_count: int = 0
    slit_width: float = 0.0
    slit_length: float = 0.0
    gauge_thickness: float | None = None  # thinned centre (None: the full thickness)
    thinning_length: float = 0.0

    @property
    def centre_thickness(self) -> float:
        """h_g: thickness over the gauge region."""
        return self.thickness if self.gauge_thickness is None else self.gauge_thickness

    def local_thickness(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """t(x, y), module docstring."""
        h, hg = self.thickness, self.centre_thickness
        if hg == h:
            return np.full(np.shape(x), h)
        s = np.maximum(np.abs(x), np.abs(y)) - self.gauge_region / 2
        u = np.clip(s / self.thinning_length, 0.0, 1.0)
        return hg + (h - hg) * (1 - np.cos(np.pi * u)) / 2

    @property
    def arm_end(self) -> float:
        """X = w/2 + ℓ: |x| (or |y|) of an arm's end."""
        return self.arm_width / 2 + self.arm_length

    @property
    def fillet_diagonal(self) -> float:
        """c: where the fillet arc crosses the diagonal x = y."""
        return self.arm_width / 2 + self.fillet_radius * (1 - math.sqrt(0.5))

    def half_width(self, x: np.ndarray) -> np.ndarray:
        """hw(x): half-width of the +x arm including the fillet bulge, for x ≥ w/2."""
        a, r = self.arm_width / 2, self.fillet_radius
        s = np.clip(a + r - np.asarray(x, float), 0.0, r)
        return a + r - np.sqrt(np.maximum(r * r - s * s, 0.0))

    def slit_strips(self) -> list[tuple[float, float]]:
        """(y_lo, y_hi) of each slit across the arm (centred on y = 0)."""
        n, s, w = self.slit_count, self.slit_width, self.arm_width
        finger = (w - n * s) / (n + 1)
        return [(-w / 2 + k * finger + (k - 1) * s, -w / 2 + k * (finger + s)) for k in range(1, n + 1)]

    def check(self) -> None:
        """Raise GeometryError naming the first impossible dimension and its allowed range."""
        for key in ("arm_width", "arm_length", "gauge_region", "thickness", "grip_length"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0):
                raise GeometryError(key, f"must be > 0 mm, got {value:g}")
        w, ell, r = self.arm_width, self.arm_length, self.fillet_radius
        if not (math.isfinite(r) and r >= 0):
            raise GeometryError("fillet_radius", f"must be >= 0 mm, got {r:g}")
        if self.gauge_region > w:
            raise GeometryError("gauge_region", f"must be in (0, arm_width = {w:g}] mm (the gauge region lies "
                                f"in the central square), got {self.gauge_region:g}")
        if not self.grip_length < ell:
            raise GeometryError("grip_length", f"must be in (0, arm_length = {ell:g}) mm, got {self.grip_length:g}")
        room = ell - self.grip_length
        if r > room:
            raise GeometryError("fillet_radius", f"= {r:g} mm is too large for the arms: it must be in "
                                f"[0, arm_length - grip_length = {room:g}] mm (the fillet must end before the grips)")
        self._check_slits()
        self._check_thinning()

    def _check_thinning(self) -> None:
        hg, lt, h, w, g = self.gauge_thickness, self.thinning_length, self.thickness, self.arm_width, self.gauge_region
        if hg is None:
            return
        if not (math.isfinite(hg) and 0 < hg < h):
            raise GeometryError("gauge_thickness", f"must be in (0, thickness = {h:g}) mm, got {hg:g}")
        room = (w - g) / 2
        if not (0 < lt <= room):
            raise GeometryError("thinning_length", f"must be in (0, (arm_width - gauge_region)/2 = {room:g}] mm "
                                f"(the ramp ends inside the central square), got {lt:g}")

    def _check_slits(self) -> None:
        n, s, sl = self.slit_count, self.slit_width, self.slit_length
        if n < 0:
            raise GeometryError("slit_count", f"must be an integer >= 0, got {n}")
        if n == 0:
            return
        w, ell, r = self.arm_width, self.arm_length, self.fillet_radius
        if not (s > 0 and n * s < w):
            raise GeometryError("slit_width", f"must be in (0, arm_width / slit_count = {w / n:g}) mm so that "
                                f"fingers remain between the slits, got {s:g}")
        if not (self.grip_length < sl <= ell - r):
            raise GeometryError("slit_length", f"must be in (grip_length = {self.grip_length:g}, arm_length - "
                                f"fillet_radius = {ell - r:g}] mm (slits run from the arm end past the grip and "
                                f"stop where the fillet begins), got {sl:g}")


def _nodes(points: list[float], lo: float, hi: float, size_at) -> np.ndarray:
    """Sorted nodes from ``lo`` to ``hi`` through the breakpoints ``points`` (duplicates and points
    outside (lo, hi) dropped); each segment evenly divided with spacing ≤ ``size_at(midpoint)``."""
    kept = [lo, hi]
    for p in sorted(points):
        if lo < p < hi and min(abs(p - k) for k in kept) > 1e-9 * max(abs(hi), 1.0):
            kept.append(p)
    kept = sorted(kept)
    out = [np.array([lo])]
    for a, b in zip(kept[:-1], kept[1:]):
        out.append(np.linspace(a, b, divisions(b - a, size_at((a + b) / 2)) + 1)[1:])
    return np.concatenate(out)


def _quadrant_grids(d: CruciformDimensions, size: float, gauge_size: float) -> list[np.ndarray]:
    """In-plane node grids (ni, nj, 2) of the central square and the two arms, x, y ≥ 0; spacing
    ≤ ``gauge_size`` over the central square and the fillets, ≤ ``size`` along the arms beyond."""
    a, X, r = d.arm_width / 2, d.arm_end, d.fillet_radius
    slit_edges = [abs(y) / a for strip in d.slit_strips() for y in strip]
    ramp_end = [(d.gauge_region / 2 + d.thinning_length) / a] if d.gauge_thickness is not None else []
    eta = _nodes([d.gauge_region / d.arm_width] + slit_edges + ramp_end, 0.0, 1.0, lambda _: gauge_size / a)
    centre = np.stack(np.meshgrid(a * eta, a * eta, indexing="ij"), axis=-1)
    points = [d.fillet_diagonal, a + r, X - d.grip_length] + ([X - d.slit_length] if d.slit_count else [])
    xs = _nodes(points, a, X, lambda mid: gauge_size if mid < a + r else size)
    top = np.minimum(xs, d.half_width(xs))
    x_arm = np.stack(np.meshgrid(xs, eta, indexing="ij"), axis=-1)
    x_arm[..., 1] *= top[:, None]
    y_arm = x_arm.transpose(1, 0, 2)[..., ::-1]
    return [centre, x_arm, y_arm]


def cruciform_unit(d: CruciformDimensions, size: float, gauge_size: float | None = None) -> Lattice:
    """The octant x, y ≥ 0, z ≥ h/2 as hexahedra in lattice order, slits cut out; a thinned centre
    maps the layers ζ ∈ [0, 1] to z = h/2 + ζ t(x, y)/2."""
    gauge_size = gauge_size or size
    h = d.thickness
    zeta = np.linspace(0.0, 1.0, divisions(d.centre_thickness / 2, min(size, gauge_size)) + 1)
    tol = 1e-9 * d.arm_end
    unit = None
    for grid in _quadrant_grids(d, size, gauge_size):
        X = np.empty(grid.shape[:2] + (len(zeta), 3))
        X[..., :2] = grid[:, :, None, :]
        X[..., 2] = h / 2 + zeta * d.local_thickness(X[..., 0], X[..., 1]) / 2
        block = Lattice.block(X)
        unit = block if unit is None else unit.join(block, tol)
    return unit.without(_in_slits(d, unit.centroids()))


def _in_slits(d: CruciformDimensions, c: np.ndarray) -> np.ndarray:
    """Cells whose centroid lies in a slit of the +x or the +y arm."""
    drop = np.zeros(len(c), bool)
    start = d.arm_end - d.slit_length
    for along, across in ((0, 1), (1, 0)):
        for lo, hi in d.slit_strips():
            drop |= (c[:, along] > start) & (c[:, across] > lo) & (c[:, across] < hi)
    return drop


def cruciform_specimen(d: CruciformDimensions, size: float, cell: str, gauge_size: float | None = None,
                       symmetry: str = "none", gauge_length: float | None = None) -> Specimen:
    """Four clamped grips over ``grip_length`` at the arm ends, moved symmetrically (centred); the
    x and y extensometers across the gauge region on the top face (gauge length ``gauge_length``,
    default the gauge region side g); the thickness marks at the centre; nominal areas w · h_g
    (arm width times the gauge thickness, h_g = h unless the centre is thinned)."""
    d.check()
    w, h, X, g = d.arm_width, d.thickness, d.arm_end, d.gauge_region
    hg = d.centre_thickness
    top, bottom = (h + hg) / 2, (h - hg) / 2
    planes = {0: 0.0, 1: 0.0, 2: h / 2}
    mirrored = mirrored_planes(symmetry)
    mesh = symmetric_mesh(cruciform_unit(d, size, gauge_size), [(a, planes[a]) for a in mirrored], cell, X)
    edge, tol = X - d.grip_length, 1e-9 * X
    grips = tuple(Grip(f"{'xy'[axis]}{'-+'[side > 0]}", axis, side,
                       (lambda X_, axis=axis, side=side: side * X_[:, axis] >= edge - tol))
                  for axis in (0, 1) for side in (-1, 1))
    e = gauge_length or g
    half = g / 2 + tol
    return Specimen(
        shape="cruciform",
        mesh=mesh,
        grips=tuple(gr for gr in grips if not (gr.side < 0 and gr.axis not in mirrored)),
        grip_separation={0: 2 * edge, 1: 2 * edge},
        extensometers={0: GaugeMarks((-e / 2, 0.0, top), (e / 2, 0.0, top)),
                       1: GaugeMarks((0.0, -e / 2, top), (0.0, e / 2, top))},
        transverse={0: GaugeMarks((0.0, -e / 2, h / 2), (0.0, e / 2, h / 2)),
                    1: GaugeMarks((-e / 2, 0.0, h / 2), (e / 2, 0.0, h / 2))},
        thickness=GaugeMarks((0.0, 0.0, bottom), (0.0, 0.0, top)),
        area0={0: w * hg, 1: w * hg},
        length_scale=float(np.linalg.norm([2 * X, 2 * X, h])),
        regions={"centre": lambda X_: (np.abs(X_[:, 0]) <= half) & (np.abs(X_[:, 1]) <= half)},
        centred=True,
        symmetry=tuple((a, planes[a]) for a in range(3) if a not in mirrored),
    )


@dataclass(frozen=True)
class CruciformSpecimen:
    shape: str
    dimensions: CruciformDimensions  # mm

    @property
    def length(self) -> float:
        return 2 * self.dimensions.arm_end

    @property
    def max_dimension(self) -> float:
        return 2 * self.dimensions.arm_end


def parse_cruciform(t: fields.Table) -> CruciformSpecimen:
    """All of arm_width, arm_length, gauge_region, fillet_radius, thickness, grip_length; slits
    optional (slit_count = 0 by default; with slits, slit_width and slit_length are required); a
    thinned centre optional (gauge_thickness with thinning_length)."""
    values: dict[str, Any] = {}
    for key in CRUCIFORM_KEYS[:6]:
        values[key] = t.number(key, ge=0) if key == "fillet_radius" else t.number(key, gt=0)
    values["slit_count"] = t.integer("slit_count", 0, 50, default=0)
    if "gauge_thickness" in t.raw:
        values["gauge_thickness"] = t.number("gauge_thickness", gt=0)
        values["thinning_length"] = t.number("thinning_length", gt=0)
    elif "thinning_length" in t.raw:
        raise SceneError(f"{t.field('thinning_length')} needs specimen.gauge_thickness (a thinned centre)")
    for key in CRUCIFORM_KEYS[7:9]:
        if values["slit_count"]:
            values[key] = t.number(key, gt=0)
        elif key in t.raw:
            raise SceneError(f"{t.field(key)} needs specimen.slit_count >= 1 (the number of slits per arm)")
    dims = CruciformDimensions(**values)
    try:
        dims.check()
    except GeometryError as exc:
        raise SceneError(f"specimen.{exc}") from None
    return CruciformSpecimen(shape="cruciform", dimensions=dims)


def count_cruciform(spec, mesh) -> MeshCount:
    """The mapper's octant: a central square of n_e × n_e cells and two arms of n_x × n_e, n_z layers
    (breakpoints at slits, fillets and ramps counted as extra divisions), mirrored 8 times."""
    d, h, hg, k = spec.dimensions, mesh.size, mesh.gauge_size or mesh.size, 2 if mesh.order == 2 else 1
    a, r = d.arm_width / 2, d.fillet_radius
    n_e = div(a, hg) + 2 * d.slit_count + 2  # breakpoints: gauge region, slit edges, thinning ramp
    n_x = div(max(r, 1e-300), hg) + div(max(d.arm_end - a - r, 1e-300), h) + 3
    n_z = div(d.centre_thickness / 2, min(h, hg))
    cut = CUT.get(mesh.symmetry, 0)  # planes cut (x, then y, then z): the octant is mirrored across the rest
    copies_plane, copies_z = 4 // (2 ** min(cut, 2)), 1 if cut == 3 else 2
    cells = copies_plane * copies_z * (n_e * n_e + 2 * n_x * n_e) * n_z * (6 if mesh.cell == "tet" else 1)
    plane = copies_plane * ((k * n_e + 1) ** 2 + 2 * k * n_x * (k * n_e + 1))
    return MeshCount(cells, plane * (copies_z * k * n_z + 1), 3, "cruciform mapper divisions")


SHAPE = Shape(
    "cruciform", CRUCIFORM_KEYS, parse_cruciform,
    lambda spec, mesh, gauge: cruciform_specimen(spec.dimensions, mesh.size, mesh.cell, mesh.gauge_size,
                                                 mesh.symmetry, gauge),
    tests={"biaxial": ("clamped",)}, symmetric=True, gauge_size=True, count=count_cruciform,
    doc="cruciform with optional slits and thinned centre, four clamped grips")
