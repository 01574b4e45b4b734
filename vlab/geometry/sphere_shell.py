"""Spherical shell: ``inner_radius`` A and ``thickness`` H (mm), outer radius B = A + H, centred at
the origin; meshed as its octant x, y, z ≥ 0 (the symmetry-reduced model of a spherically
symmetric test: inflation, vlab.loading.kinds.inflation).

Hexahedra over three patches of the octant's sphere, each the projection of one face of the
cube corner [0, 1]³ (the faces x = 1, y = 1, z = 1), by equal angles: the face point
(1, tan(π s/4), tan(π t/4)), s, t ∈ [0, 1], normalized (a "cubed sphere"), n_s × n_s cells per
patch, and n_h layers through the thickness:

    n_s = ⌈π B / (4 h)⌉,  n_h = ⌈H / h⌉   (h = mesh.size),  elements 3 n_s² n_h.

Every node of a patch lies on a sphere of its layer's radius, so the inner and outer surfaces are
inscribed polyhedra (facets whose corners are on r = A and r = B). The three patches meet at the
octant's centre direction (1, 1, 1)/√3 at 120°.

Named places: the region "inner" selects the nodes on r = A (the cavity), the planes x = 0,
y = 0, z = 0 are the symmetry planes (Specimen.symmetry: the readings are the full shell's); the
gauge marks are the outer-surface points (B, 0, 0) and (0, B, 0) (their chord reads the outer hoop
stretch) and the wall (A, 0, 0)–(B, 0, 0) (the thickness).

The renders look at the cut plane y = 0 nearly face-on (view direction (0.3, −1, 0.3), z up): the
balloon's profile as a lab photographs it from the side, the wall's section on the cut, and the
undeformed octant, which lies inside the inflated one, not hidden behind it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.counts import MeshCount, div
from vlab.geometry.lattice import Lattice
from vlab.geometry.shape import Shape
from vlab.geometry.specimen import GaugeMarks, Specimen, View

__all__ = ["SphereShellSpecimen", "shell_divisions", "shell_mesh", "cavity_volume", "SHAPE"]


@dataclass(frozen=True)
class SphereShellSpecimen:
    shape: str
    inner_radius: float  # mm
    thickness: float  # mm

    @property
    def outer_radius(self) -> float:
        return self.inner_radius + self.thickness

    @property
    def length(self) -> float:
        return self.outer_radius

    @property
    def max_dimension(self) -> float:
        return self.outer_radius


def parse_shell(t: fields.Table) -> SphereShellSpecimen:
    inner = t.number("inner_radius", gt=0, note=" (mm)")
    thickness = t.number("thickness", gt=0, note=" (mm)")
    return SphereShellSpecimen(shape="sphere-shell", inner_radius=inner, thickness=thickness)


def shell_divisions(inner: float, thickness: float, size: float) -> tuple[int, int]:
    """(n_s, n_h) of the module docstring."""
    return div(math.pi * (inner + thickness) / 4.0, size), div(thickness, size)


def _patch_directions(n_s: int) -> list[np.ndarray]:
    """Unit directions (n_s + 1, n_s + 1, 3) of the three patches."""
    tan = np.tan(np.linspace(0.0, math.pi / 4, n_s + 1))
    s, t = np.meshgrid(tan, tan, indexing="ij")
    one = np.ones_like(s)
    faces = [np.stack([one, s, t], -1), np.stack([t, one, s], -1), np.stack([s, t, one], -1)]
    return [f / np.linalg.norm(f, axis=-1, keepdims=True) for f in faces]


def shell_mesh(inner: float, thickness: float, size: float):
    """The octant's hexahedral MeshHex (module docstring)."""
    n_s, n_h = shell_divisions(inner, thickness, size)
    radii = np.linspace(inner, inner + thickness, n_h + 1)
    lattice = None
    for d in _patch_directions(n_s):
        X = d[:, :, None, :] * radii[None, None, :, None]  # (s, t, r, 3)
        e_s, e_t, e_r = X[1, 0, 0] - X[0, 0, 0], X[0, 1, 0] - X[0, 0, 0], X[0, 0, 1] - X[0, 0, 0]
        if np.dot(np.cross(e_s, e_t), e_r) < 0:  # lattice order must be right-handed
            X = X[::-1]
        part = Lattice.block(np.ascontiguousarray(X))
        lattice = part if lattice is None else lattice.join(part, 1e-9 * (inner + thickness))
    return lattice.to_mesh("hex")


def cavity_volume(mesh, inner: float) -> float:
    """The octant's cavity volume (mm³) bounded by the meshed inner surface and the symmetry
    planes: Σ over the inner facets of the cone to the origin, (1/3) Σ x_c · n_f A_f, with each
    quadrilateral facet split into two triangles (exact for the facetted surface):
    V = Σ_f (|P₀ · (P₁ × P₂)| + |P₀ · (P₂ × P₃)|) / 6, the corners P in cyclic order."""
    r = np.linalg.norm(mesh.p, axis=0)
    facets = mesh.boundary_facets()
    nodes = mesh.facets[:, facets]
    on_inner = np.all(np.abs(r[nodes] - inner) <= 1e-9 * inner, axis=0)
    P = np.transpose(mesh.p[:, nodes[:, on_inner]], (2, 1, 0))  # (facet, corner, xyz)
    # the facet's nodes in cyclic order: scikit-fem stores hex facets as (0, 1, 2, 3) around
    P = np.take_along_axis(P, _cyclic(P)[:, :, None], axis=1)
    volume = (np.abs(np.einsum("fi,fi->f", P[:, 0], np.cross(P[:, 1], P[:, 2])))
              + np.abs(np.einsum("fi,fi->f", P[:, 0], np.cross(P[:, 2], P[:, 3])))) / 6.0
    return float(np.sum(volume))


def _cyclic(P: np.ndarray) -> np.ndarray:
    """The order of each planar-ish quadrilateral's four corners around its centroid, for
    P of shape (facets, 4, 3)."""
    c = P.mean(axis=1, keepdims=True)
    n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    degenerate = np.linalg.norm(n, axis=1) < 1e-300
    n[degenerate] = np.cross(P[degenerate, 1] - P[degenerate, 0], P[degenerate, 3] - P[degenerate, 0])
    u = P[:, 0] - c[:, 0]
    v = np.cross(n, u)
    d = P - c
    angle = np.arctan2(np.einsum("fki,fi->fk", d, v) / np.linalg.norm(v, axis=1)[:, None],
                       np.einsum("fki,fi->fk", d, u) / np.linalg.norm(u, axis=1)[:, None])
    return np.argsort(angle, axis=1)


def shell_specimen(spec: SphereShellSpecimen, element_size: float, cell: str) -> Specimen:
    A, B = spec.inner_radius, spec.outer_radius
    if cell != "hex":
        raise SceneError(f"mesh.cell must be 'hex' for specimen.shape = 'sphere-shell' (a cubed-sphere octant of "
                         f"hexahedra), got {cell!r}")
    mesh = shell_mesh(A, spec.thickness, element_size)
    return Specimen(
        shape="sphere-shell",
        mesh=mesh,
        grips=(),
        grip_separation={0: A},
        extensometers={0: GaugeMarks((B, 0.0, 0.0), (0.0, B, 0.0))},
        transverse={0: GaugeMarks((0.0, 0.0, A), (0.0, 0.0, B))},
        thickness=GaugeMarks((A, 0.0, 0.0), (B, 0.0, 0.0)),
        area0={0: cavity_volume(mesh, A)},  # the octant's cavity volume, mm³ (the pressure reader's V₀)
        length_scale=B,
        regions={"inner": lambda X: np.abs(np.linalg.norm(X, axis=1) - A) <= 1e-9 * A},
        view=View(direction=(0.3, -1.0, 0.3), up=(0.0, 0.0, 1.0)),
    )


def count_shell(spec, mesh) -> MeshCount:
    """3 n_s² n_h hexahedra; nodes per layer 3 n_s² + 3 n_s + 1 (three patches sharing three edges
    and the centre), (p n) for order p."""
    n_s, n_h = shell_divisions(spec.inner_radius, spec.thickness, mesh.size)
    p = 2 if mesh.order == 2 else 1
    m = p * n_s
    return MeshCount(3 * n_s * n_s * n_h, (3 * m * m + 3 * m + 1) * (p * n_h + 1), 3, "cubed-sphere octant")


SHAPE = Shape(
    "sphere-shell", ("inner_radius", "thickness"), parse_shell,
    lambda spec, mesh, gauge: shell_specimen(spec, mesh.size, mesh.cell),
    tests={"inflation": ("cavity",)}, thickness=lambda spec: spec.thickness, count=count_shell,
    doc="spherical shell (a balloon), meshed as its octant: inflation under volume control",
    gauge_from="the shell's hoop (the inflation test reads the inner hoop stretch)")
