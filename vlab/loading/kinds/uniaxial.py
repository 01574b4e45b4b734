"""Uniaxial tension or compression: ``stretch = λ`` (one number, 0.2..10).

Grips move along x; on the roller block (or a sheet) the oracle is F = diag(λ, t, t) with the
lateral faces free, P₂₂ = P₃₃ = 0 (materials.homogeneous.uniaxial; plane strain: diag(λ, t, 1)).
Measures Young's modulus E = slope of the engineering stress F/A₀ against the extensometer strain
and Poisson's ratio ν = −slope of the transverse against the axial strain, over the modulus window
(measure/elastic_constants.py); the crosshead modulus beside them.
"""

from __future__ import annotations

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import PlotSpec, TestKind, stretch_value


class Uniaxial(TestKind):
    name = "uniaxial"
    axes = (0,)
    oracle_setups = {"block": "roller", "sheet": "roller"}
    cyclic = True
    effects = True
    lateral_ratio = True
    plot = PlotSpec("strain", "stress", "engineering strain [–] (extensometer)", "engineering stress [MPa]",
                    (("strain", "stress", "stress_x"),))
    doc = "uniaxial tension or compression along x"
    fit, crosshead_fit = "uniaxial", "crosshead"  # E and ν; the crosshead modulus (vlab/measure/kinds.py)

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        v = t.get("stretch")
        if isinstance(v, list):
            raise SceneError(f"{t.field('stretch')} must be a single number for kind = 'uniaxial', "
                             f"got {fields.show(v)}")
        return (stretch_value(t.field("stretch"), v),)

    def loading(self, specimen, X, test):
        """The grips' prescribed displacements; a misaligned moving grip (test.misalignment) also
        moves laterally and turns (vlab.loading.misalignment)."""
        loading = super().loading(specimen, X, test)
        if test.misalignment is None:
            return loading
        import dataclasses

        from vlab.loading.misalignment import misalign

        u_hat = misalign(loading.u_hat, X, loading.moving_dofs[0], *test.misalignment)
        return dataclasses.replace(loading, u_hat=u_hat)

    def state(self, material, values):
        from vlab.materials.homogeneous import homogeneous_uniaxial

        return homogeneous_uniaxial(material, values[0])

    def isochoric(self, values):
        import numpy as np

        lam = values[0]
        return np.diag([lam, lam**-0.5, lam**-0.5])  # F = diag(λ, λ^(−1/2), λ^(−1/2))

    def columns(self, curve) -> dict[str, list[float]]:
        return super().columns(curve) | {"crosshead_strain": curve.crosshead_strain(0).tolist()}


UNIAXIAL = Uniaxial()
