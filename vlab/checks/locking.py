"""Volumetric locking of displacement-only elements, and the stops it can fake.

A displacement-only element of a near-incompressible solid (ν > LOCKING_NU) must keep J ≈ 1 at
every quadrature point with too few displacement DOFs: wherever the field is not uniform (clamped
grips, shear plates, an imperfection, self-weight) it locks, its pressure oscillates from point to
point and the stiffness comes out too high. The same spurious stresses enter the geometric part of
the tangent, so a locked mesh's K_ff can turn indefinite where the solid is stable: a clamped
Mooney–Rivlin planar-tension strip (4 × 40 × 1 mm, mesh.size 1, one hexahedron through the
thickness, K/μ = 143) shows two negative eigenvalues at stretch 1.216 with a mode flapping its
free ends at mid-height while the material is strongly elliptic; the same mesh with the mixed
formulation, or the displacement mesh halved, reaches stretch 1.5 positive definite
(docs/reference/tests.md, planar tension).

``locking_prone(scene)`` is the condition of the run's locking warning; ``locking_free(scene)``
the same scene with ``mesh.formulation = "mixed"`` when the user left the formulation at its
default and the mixed body applies (a split law, hexahedra or order-2 tetrahedra), else None.
"""

from __future__ import annotations

from vlab.fields import SceneError

LOCKING_NU = 0.45  # above this, displacement-only elements lock on non-uniform fields


def uniform_field(scene) -> bool:
    """The test's deformation is uniform on every mesh (the kind's exact homogeneous state for this
    shape and grips, e.g. the roller block or the kinematic shear block; no imperfection, no
    self-weight): a displacement-only element cannot lock there."""
    from vlab.loading.kinds import kind_of

    kind = kind_of(scene.test)
    return (kind.has_oracle(scene.specimen.shape, scene.test.grips) and scene.test.imperfection is None
            and scene.effect("gravity") is None)


def locking_prone(scene) -> bool:
    """ν > LOCKING_NU on displacement-only elements over a non-uniform field."""
    return (scene.material.moduli.nu > LOCKING_NU and scene.mesh.formulation == "displacement"
            and not uniform_field(scene))


def locking_free(scene):
    """The scene with mesh.formulation = "mixed" (same mesh, same everything else), or None when the
    user chose the formulation or the mixed body does not apply to this law or cell."""
    from vlab.scene import apply_overrides, parse_scene

    if not locking_prone(scene) or "formulation" in (scene.source.get("mesh") or {}):
        return None
    try:
        return parse_scene(apply_overrides(scene.source, {"mesh.formulation": "mixed"}), base_dir=scene.base_dir)
    except SceneError:  # no volumetric–isochoric split, or linear tetrahedra
        return None
