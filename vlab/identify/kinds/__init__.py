"""Closed-form data kinds of `vlab fit` beyond the homogeneous states of vlab.identify.states:
their registry ``FIT_KINDS`` ({name: FitKind}, the contract in .base).

torsion.py      torque and axial force against twist of an incompressible cylinder (Rivlin's
                integrals for any isotropic law), [data.geometry] radius
inflation.py    pressure against inner hoop stretch of an incompressible thick sphere (the
                closed form of vlab.loading.thick_sphere), [data.geometry] inner_radius, thickness
tension_torsion.py  torque and axial force of the same cylinder held at an axial stretch λ,
                [data.geometry] radius, stretch
free_torsion.py the axial stretch (and torque) of the cylinder with a free end: N(ψ, λ) = 0
confined.py     axial stress of the die's homogeneous F = diag(λ, 1, 1) (a compressible card)

The fit file parser (vlab.identify.fitfile) reads their columns, units and geometry from the
registry; vlab.identify.solve.predict, max_I1 and modulus_scale dispatch to them; a new kind is
one module and one entry here.
"""

from __future__ import annotations

from vlab.identify.kinds import confined, free_torsion, inflation, tension_torsion, torsion
from vlab.identify.kinds.base import FitKind, outputs_of

__all__ = ["FIT_KINDS", "FitKind", "outputs_of"]

FIT_KINDS: dict[str, FitKind] = {m.KIND.name: m.KIND for m in (torsion, tension_torsion, free_torsion, inflation, confined)}
