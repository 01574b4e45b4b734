"""A dogbone meshed by Gmsh's Delaunay tetrahedra instead of vlab's hexahedra split into
tetrahedra (``[mesh] mesher = "gmsh"``, ``cell = "tet"``; the ``cad`` extra). The outline is the
same as vlab's (geometry/dogbone.py: the parallel section, one fillet arc of radius r tangent to it
or the S-curve r / r_o, the tabs), drawn exactly with OpenCASCADE arcs; two cuts across the tabs at
the grip edges (x = g, L − g) make the grips select whole faces of nodes. Element edge ≤ ``size``,
≤ ``gauge_size`` over the parallel section and fillets (a Box size field). The mesh is not mirror
symmetric, so [mesh] symmetry stays "none".
"""

from __future__ import annotations

import math

import numpy as np
import skfem

from vlab.geometry.cad import _session, in_own_process
from vlab.geometry.dogbone import DogboneDimensions


def _upper_right(d: DogboneDimensions) -> list[tuple]:
    """The outline's upper-right quarter from the parallel end to the tab end: ("line", a, b) or
    ("arc", a, centre, b) in (x, y), x measured from the centre."""
    b1, b2, r, ro = d.width / 2, d.end_width / 2, d.fillet_radius, d.outer_radius
    xp, st = d.parallel_length / 2, d.transition_length
    if ro == 0.0:
        segs = [("arc", (xp, b1), (xp, b1 + r), (xp + st, b2))]
    else:
        sj = d.arc_junction
        yj = b1 + r - math.sqrt(r * r - sj * sj)
        segs = [("arc", (xp, b1), (xp, b1 + r), (xp + sj, yj)),
                ("arc", (xp + sj, yj), (xp + st, b2 - ro), (xp + st, b2))]
    if xp + st < d.overall_length / 2 - 1e-9:
        segs.append(("line", (xp + st, b2), (d.overall_length / 2, b2)))
    return segs


def _outline(d: DogboneDimensions) -> list[tuple]:
    """The whole outline, counter-clockwise from (0, −b2/2), as segments in (x, y), 0 ≤ x ≤ L."""
    quarter = _upper_right(d)  # from (xp, b1/2) to (L/2, b2/2), x from the centre
    L, xp, b1, b2 = d.overall_length, d.parallel_length / 2, d.width / 2, d.end_width / 2

    def flipped(sx, sy):  # the quarter mirrored, same direction (outward from the parallel end)
        return [(seg[0], *[(sx * x, sy * y) for x, y in seg[1:]]) for seg in quarter]

    def backwards(segs):
        return [(seg[0], *seg[1:][::-1]) for seg in segs[::-1]]

    e = L / 2
    out = (backwards(flipped(-1, -1)) + [("line", (-xp, -b1), (xp, -b1))] + flipped(1, -1)
           + [("line", (e, -b2), (e, b2))] + backwards(quarter) + [("line", (xp, b1), (-xp, b1))]
           + flipped(-1, 1) + [("line", (-e, b2), (-e, -b2))])
    return [(seg[0], *[(x + e, y) for x, y in seg[1:]]) for seg in out]


def gmsh_dogbone_mesh(d: DogboneDimensions, size: float, gauge_size: float | None = None) -> skfem.MeshTet:
    """Gmsh tetrahedra of the dogbone (module docstring), as a scikit-fem mesh, mm (Gmsh runs in its
    own process: vlab.geometry.cad.in_own_process says why)."""
    P, tets = in_own_process(_gmsh_tets, d, size, gauge_size or size)
    return skfem.MeshTet(np.ascontiguousarray(P.T), np.ascontiguousarray(tets.T))


def _gmsh_tets(d: DogboneDimensions, size: float, gauge_size: float) -> tuple[np.ndarray, np.ndarray]:
    with _session() as gmsh:
        _solid(gmsh, d)
        _size_field(gmsh, d, size, gauge_size)
        # Netgen's optimiser after Gmsh's: Gmsh alone left slivers (scaled Jacobian 0.03) that vlab's
        # mesh check refuses, on the ISO 527-2 1A dogbone at mesh.size 2.83
        gmsh.option.setNumber("Mesh.OptimizeNetgen", 1)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, nodes = gmsh.model.mesh.getElementsByType(4)
    return _positive_tets(coords.reshape(-1, 3), tags, nodes)


def _solid(gmsh, d: DogboneDimensions) -> None:
    """The outline (exact arcs) as a face cut at the grip edges x = g and L − g, extruded through
    the thickness, duplicates merged."""
    L, h, b2 = d.overall_length, d.thickness, d.end_width / 2
    occ = gmsh.model.occ
    points: dict[tuple, int] = {}

    def point(xy):
        key = (round(xy[0], 9), round(xy[1], 9))
        if key not in points:
            points[key] = occ.addPoint(xy[0], xy[1], 0.0)
        return points[key]

    curves = [occ.addLine(point(s[1]), point(s[2])) if s[0] == "line" else
              occ.addCircleArc(point(s[1]), point(s[2]), point(s[3])) for s in _outline(d)]
    face = occ.addPlaneSurface([occ.addCurveLoop(curves)])
    g = d.grip_length
    cuts = [occ.addLine(occ.addPoint(x, -2 * b2, 0), occ.addPoint(x, 2 * b2, 0)) for x in (g, L - g)]
    pieces, _ = occ.fragment([(2, face)], [(1, c) for c in cuts])
    faces = [t for t in pieces if t[0] == 2]
    occ.synchronize()
    loose = [(1, c) for _, c in gmsh.model.getEntities(1) if len(gmsh.model.getAdjacencies(1, c)[0]) == 0]
    occ.remove(loose, recursive=True)
    occ.extrude(faces, 0, 0, h)
    occ.removeAllDuplicates()
    occ.synchronize()


def _size_field(gmsh, d: DogboneDimensions, size: float, gauge_size: float) -> None:
    """Element size gauge_size over the parallel section and fillets (a box field), size elsewhere."""
    L, h, b2 = d.overall_length, d.thickness, d.end_width / 2
    field = gmsh.model.mesh.field.add("Box")
    reach = d.parallel_length / 2 + d.transition_length
    for key, value in (("VIn", gauge_size), ("VOut", size), ("XMin", L / 2 - reach), ("XMax", L / 2 + reach),
                       ("YMin", -2 * b2), ("YMax", 2 * b2), ("ZMin", -h), ("ZMax", 2 * h)):
        gmsh.model.mesh.field.setNumber(field, key, value)
    gmsh.model.mesh.field.setAsBackgroundMesh(field)
    gmsh.option.setNumber("Mesh.MeshSizeMax", float(size))
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)


def _positive_tets(X: np.ndarray, tags, nodes) -> tuple[np.ndarray, np.ndarray]:
    """(points, tets) of Gmsh's nodes and 4-node tetrahedra: unused nodes dropped, every
    tetrahedron ordered to a positive volume (scikit-fem's convention)."""
    index = np.empty(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    tets = index[nodes.astype(np.int64)].reshape(-1, 4)
    used, tets = np.unique(tets, return_inverse=True)
    tets = tets.reshape(-1, 4)
    P = X[used]
    a, b, c, e = (P[tets[:, k]] for k in range(4))
    flip = np.einsum("ij,ij->i", np.cross(b - a, c - a), e - a) < 0
    tets[flip, 0], tets[flip, 1] = tets[flip, 1], tets[flip, 0].copy()
    return P, tets
