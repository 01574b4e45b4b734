"""Tensile dogbone (dumbbell) specimens: outline, validation, structured mesh, grips and gauge marks.

Outline (x along the specimen, 0 ≤ x ≤ overall_length; y across the width, centred; z through the
thickness, 0 ≤ z ≤ thickness). Measured from the end of the parallel section, s = |x − L/2| − l1/2,
the half-width is b1/2 in the parallel section (s ≤ 0) and b2/2 on the tabs; between them the
transition of step d = (b2 − b1)/2 is

- one arc of radius r tangent to the parallel section (ISO 527-2 1A/1BA):
      y(s) = b1/2 + r − √(r² − s²),   transition length s_t = √(d (2r − d))  (needs r ≥ d);
- an S-curve (ASTM D638 IV, ISO 37, ASTM D412): the concave arc r tangent to the parallel section,
  then a convex arc r_o tangent to the tab, meeting at slope angle θ with cos θ = 1 − d/(r + r_o):
      y(s) = b1/2 + r − √(r² − s²)                 for s ≤ r sin θ,
      y(s) = b2/2 − r_o + √(r_o² − (s_t − s)²)     up to s_t = (r + r_o) sin θ.

Mesh: a structured block in (x, η, z), η ∈ [−1, 1], mapped by y = η · half_width(x). Mesh lines sit
at the grip edges, the ends of the parallel section and the arc junctions, so the parallel section
is meshed with undistorted boxes (a homogeneous uniaxial state is represented exactly there) and
the grips select whole element layers. One octant (x ≥ L/2, η ≥ 0, z ≥ h/2) of hexahedra, or of
their Kuhn split into tetrahedra, is mirrored across the mid-planes (geometry/lattice.py), so the
mesh is symmetric and ``[mesh] symmetry`` can keep half, a quarter or an eighth of it. (Why not Gmsh
by default: the PyPI ``gmsh`` wheel's libgmsh links libGLU, libGL, libXrender, libXft, libXcursor,
libXinerama and libX11 — ldd on gmsh 4.15.2 — which a pip-only machine need not have; this mesher
needs only numpy and scikit-fem. ``[mesh] mesher = "gmsh"`` offers Gmsh's tetrahedra of the same
outline where it is installed: geometry/gmsh_dogbone.py.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import skfem

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.counts import CUT, MeshCount, div, lattice_count
from vlab.geometry.shape import Shape

from vlab.geometry.lattice import Lattice, divisions, symmetric_mesh
from vlab.geometry.specimen import GaugeMarks, Grip, Specimen
from vlab.geometry.symmetry import cut_axes, mirrored_planes

DIMENSION_KEYS = ("overall_length", "gauge_length", "parallel_length", "width", "end_width",
                  "fillet_radius", "outer_radius", "thickness", "grip_length")


class GeometryError(ValueError):
    """Impossible dimensions; ``field`` names the offending dimension key."""

    def __init__(self, field: str, message: str):
        super().__init__(f"{field} {message}")
        self.field = field


@dataclass(frozen=True)
class DogboneDimensions:
    """A dogbone's dimensions, mm. ``outer_radius`` = 0 means a single fillet arc."""

    overall_length: float
    gauge_length: float
    parallel_length: float
    width: float
    end_width: float
    fillet_radius: float
    thickness: float
    grip_length: float
    outer_radius: float = 0.0
    standard: str = ""

    @property
    def step(self) -> float:
        """d = (b2 − b1)/2, the half-width change across each transition, mm."""
        return (self.end_width - self.width) / 2

    @property
    def _sin_cos(self) -> tuple[float, float]:
        """Slope angle θ where the S-curve's arcs meet (compound fillets only)."""
        c = 1.0 - self.step / (self.fillet_radius + self.outer_radius)
        return math.sqrt(max(0.0, 1.0 - c * c)), c

    @property
    def transition_length(self) -> float:
        """s_t: axial length of one fillet transition, mm."""
        d, r = self.step, self.fillet_radius
        if self.outer_radius == 0.0:
            return math.sqrt(max(0.0, d * (2 * r - d)))
        return (r + self.outer_radius) * self._sin_cos[0]

    @property
    def arc_junction(self) -> float | None:
        """s where the concave arc meets the convex one (None for a single arc)."""
        return None if self.outer_radius == 0.0 else self.fillet_radius * self._sin_cos[0]

    def half_width(self, x: np.ndarray) -> np.ndarray:
        """Half-width y_max(x) of the outline, mm."""
        L, l1, b1, b2 = self.overall_length, self.parallel_length, self.width, self.end_width
        r, ro, st = self.fillet_radius, self.outer_radius, self.transition_length
        s = np.clip(np.abs(np.asarray(x, float) - L / 2) - l1 / 2, 0.0, st)
        concave = b1 / 2 + r - np.sqrt(np.maximum(r * r - s * s, 0.0))
        if ro == 0.0:
            return np.where(s >= st, b2 / 2, concave)
        convex = b2 / 2 - ro + np.sqrt(np.maximum(ro * ro - (st - s) ** 2, 0.0))
        return np.where(s <= self.arc_junction, concave, convex)

    def check(self) -> None:
        """Raise GeometryError naming the first impossible dimension."""
        for key in DIMENSION_KEYS:
            value = getattr(self, key)
            if key == "outer_radius" and value == 0.0:
                continue
            if not (math.isfinite(value) and value > 0):
                raise GeometryError(key, f"must be > 0 mm, got {value:g}")
        if not self.end_width > self.width:
            raise GeometryError("end_width", f"must be > width = {self.width:g} mm, got {self.end_width:g}")
        if not self.parallel_length < self.overall_length:
            raise GeometryError("parallel_length", f"must be < overall_length = {self.overall_length:g} mm, "
                                f"got {self.parallel_length:g}")
        if self.gauge_length > self.parallel_length:
            raise GeometryError("gauge_length", f"must be <= parallel_length = {self.parallel_length:g} mm "
                                f"(the gauge marks sit in the parallel section), got {self.gauge_length:g}")
        self._check_fillet()
        room = (self.overall_length - self.parallel_length) / 2
        if not self.grip_length < room:
            raise GeometryError("grip_length", f"must be < (overall_length - parallel_length)/2 = {room:g} mm "
                                f"(grips must stay off the parallel section), got {self.grip_length:g}")

    def _check_fillet(self) -> None:
        d, r, ro = self.step, self.fillet_radius, self.outer_radius
        if ro == 0.0 and r < d:
            raise GeometryError("fillet_radius", f"must be >= (end_width - width)/2 = {d:g} mm for one "
                                f"tangent arc to reach the end width, got {r:g}")
        if ro > 0.0 and r + ro < d:
            raise GeometryError("fillet_radius", f"+ outer_radius must be >= (end_width - width)/2 = {d:g} mm, "
                                f"got {r + ro:g}")
        room = (self.overall_length - self.parallel_length) / 2
        if self.transition_length > room * (1 + 1e-9):
            raise GeometryError("fillet_radius", f"= {r:g} mm is larger than possible: its transition needs "
                                f"{self.transition_length:.4g} mm each side but (overall_length - "
                                f"parallel_length)/2 = {room:g} mm")


def _axial_nodes(dims: DogboneDimensions, size: float, gauge_size: float) -> np.ndarray:
    """x coordinates of the mesh planes: breakpoints at the parallel ends, arc junctions, tab
    starts and grip edges; spacing ≤ gauge_size over the parallel section and fillets, ≤ size on
    the tabs. A grip edge closer than a fifth of an element to an outline breakpoint is snapped to
    it (the grip then holds to that plane) rather than leaving a sliver element."""
    L, half = dims.overall_length, dims.parallel_length / 2
    st, sj = dims.transition_length, dims.arc_junction
    offsets = [half, half + st] + ([half + sj] if sj is not None else [])
    outline = sorted({0.0, L, L / 2} | {L / 2 + sign * o for o in offsets for sign in (-1, 1)})
    breaks = list(outline)
    for g in (dims.grip_length, L - dims.grip_length):
        if min(abs(g - b) for b in outline) > 0.2 * size:
            breaks.append(g)
    points = np.array(sorted(breaks))
    xs = [points[:1]]
    for a, b in zip(points[:-1], points[1:]):
        fine = abs((a + b) / 2 - L / 2) < half + st
        h = gauge_size if fine else size
        xs.append(np.linspace(a, b, max(1, math.ceil((b - a) / h - 1e-9)) + 1)[1:])
    return np.concatenate(xs)


def dogbone_mesh(dims: DogboneDimensions, size: float, cell: str, gauge_size: float | None = None,
                 symmetry: str = "none") -> skfem.Mesh:
    """Structured mesh of the outline (module docstring); element edge ≈ ``size`` mm,
    ≈ ``gauge_size`` over the parallel section and fillets (default ``size``)."""
    gauge_size = gauge_size or size
    L, h = dims.overall_length, dims.thickness
    xs = _axial_nodes(dims, size, gauge_size)
    xs = xs[xs >= L / 2 - 1e-9 * L]
    eta = np.linspace(0.0, 1.0, divisions(dims.width / 2, gauge_size) + 1)
    zs = np.linspace(h / 2, h, divisions(h / 2, min(size, gauge_size)) + 1)
    X = np.stack(np.meshgrid(xs, eta, zs, indexing="ij"), axis=-1)
    X[..., 1] *= dims.half_width(X[..., 0])
    planes = {0: L / 2, 1: 0.0, 2: h / 2}
    return symmetric_mesh(Lattice.block(X), [(a, planes[a]) for a in mirrored_planes(symmetry)], cell, L)


def _regions(dims: DogboneDimensions, xc: float, g: float, tol: float) -> dict:
    """The gauge section, and the fillets less a Saint-Venant distance (one end width) from the
    clamp edge g, whose corner singularity is the grip's and not the fillet's."""
    G = dims.gauge_length
    fillet_end = min(dims.parallel_length / 2 + dims.transition_length, xc - g - dims.end_width / 2)
    return {
        "gauge": lambda X: np.abs(X[:, 0] - xc) <= G / 2 + tol,
        "fillets": lambda X: ((np.abs(X[:, 0] - xc) >= dims.parallel_length / 2 - tol)
                              & (np.abs(X[:, 0] - xc) <= fillet_end + tol)),
    }


def dogbone_specimen(dims: DogboneDimensions, size: float, cell: str, gauge_size: float | None = None,
                     symmetry: str = "none", mesher: str = "vlab") -> Specimen:
    """Clamped grips over ``grip_length`` (snapped to the nearest mesh plane) at each end; gauge marks of ``gauge_length`` centred on
    the top face; transverse marks across the width and thickness marks at the gauge centre.
    ``mesher = "gmsh"``: Gmsh's tetrahedra of the same outline (geometry/gmsh_dogbone.py)."""
    dims.check()
    L, G, b1, h = dims.overall_length, dims.gauge_length, dims.width, dims.thickness
    if mesher == "gmsh":
        from vlab.geometry.gmsh_dogbone import gmsh_dogbone_mesh

        mesh = gmsh_dogbone_mesh(dims, size, gauge_size)
    else:
        mesh = dogbone_mesh(dims, size, cell, gauge_size, symmetry)
    planes = np.unique(mesh.p[0])
    g = L - float(planes[np.argmin(np.abs(planes - (L - dims.grip_length)))])  # the meshed grip edge
    tol = 1e-9 * L
    xc = L / 2
    cut = cut_axes(symmetry)
    grips = (Grip("x-", 0, -1, lambda X: X[:, 0] <= g + tol),
             Grip("x+", 0, +1, lambda X: X[:, 0] >= L - g - tol))[1 if 0 in cut else 0:]
    regions = _regions(dims, xc, g, tol)
    return Specimen(
        shape="dogbone",
        mesh=mesh,
        grips=grips,
        grip_separation={0: L - 2 * g},
        extensometers={0: GaugeMarks((xc - G / 2, 0.0, h), (xc + G / 2, 0.0, h))},
        transverse={0: GaugeMarks((xc, -b1 / 2, h / 2), (xc, b1 / 2, h / 2))},
        thickness=GaugeMarks((xc, 0.0, 0.0), (xc, 0.0, h)),
        area0={0: b1 * h},
        length_scale=float(np.linalg.norm([L, dims.end_width, h])),
        regions=regions,
        symmetry=tuple((a, {0: xc, 1: 0.0, 2: h / 2}[a]) for a in cut),
    )


@dataclass(frozen=True)
class DogboneSpecimen:
    shape: str
    dimensions: DogboneDimensions  # mm; dimensions.standard names the source ("" if explicit)

    @property
    def length(self) -> float:
        return self.dimensions.overall_length

    @property
    def max_dimension(self) -> float:
        return self.dimensions.overall_length


def parse_dogbone(t: fields.Table) -> DogboneSpecimen:
    """``standard = "<name>"`` loads the shipped dimensions; explicit keys override them."""
    from vlab.geometry.standards import standard_dimensions, standard_names

    values: dict[str, Any] = {"outer_radius": 0.0}
    standard = t.get("standard", "")
    if "standard" in t.raw:
        data = standard_dimensions(standard) if isinstance(standard, str) else None
        if data is None:
            raise SceneError(f"{t.field('standard')} must be one of {', '.join(standard_names())}; "
                             f"got {fields.show(standard)}{fields.suggest(str(standard), standard_names())}")
        standard = data.pop("standard")
        values.update(data)
    for key in DIMENSION_KEYS:
        if key in t.raw:
            values[key] = t.number(key, ge=0) if key == "outer_radius" else t.number(key, gt=0)
        elif key not in values:
            raise SceneError(f"missing required key {t.field(key)} (or give specimen.standard, one of "
                             f"{', '.join(standard_names())})")
    dims = DogboneDimensions(**values, standard=standard)
    try:
        dims.check()
    except GeometryError as exc:
        raise SceneError(f"specimen.{exc}") from None
    return DogboneSpecimen(shape="dogbone", dimensions=dims)


def count_dogbone(spec, mesh) -> MeshCount:
    """The structured mapper's divisions: along x ceil(l_fine / h_g) + ceil(l_tabs / h) with l_fine =
    parallel length + 2 × transition, across 2 ceil(w / 2 h_g), through 2 ceil(t / 2 min(h, h_g))."""
    d, h, hg = spec.dimensions, mesh.size, mesh.gauge_size or mesh.size
    fine = min(d.overall_length, d.parallel_length + 2 * d.transition_length)
    n = (div(fine, hg) + div(max(d.overall_length - fine, 0.0), h) if d.overall_length > fine else div(fine, hg),
         2 * div(d.width / 2, hg), 2 * div(d.thickness / 2, min(h, hg)))
    cut = CUT.get(mesh.symmetry, 0)
    return lattice_count(tuple(-(-k // 2) if a < cut else k for a, k in enumerate(n)), mesh,
                         "dogbone mapper divisions")


SHAPE = Shape(
    "dogbone", ("standard",) + DIMENSION_KEYS, parse_dogbone,
    lambda spec, mesh, gauge: dogbone_specimen(spec.dimensions, mesh.size, mesh.cell, mesh.gauge_size, mesh.symmetry,
                                                      mesh.mesher),
    tests={"uniaxial": ("clamped",)}, symmetric=True, gauge_size=True,
    thickness=lambda spec: float(min(spec.dimensions.thickness, spec.dimensions.width)), count=count_dogbone,
    doc="standard or custom dumb-bell between clamped grips",
    gauge_from="specimen.gauge_length (the standard's or the custom dumb-bell's gauge marks)")
