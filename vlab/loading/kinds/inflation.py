"""Inflation of a spherical shell (a balloon) under volume control: ``stretch = λ_a`` (the final
hoop stretch of the inner surface, 1 < λ_a ≤ 10), ``control = "volume"`` (the only control in this
build: the cavity volume V = λ_a³ V₀ is prescribed through its wall, vlab.loading.inflation, so the
test passes the pressure maximum), ``grips = "cavity"``.

Records per level: ``stretch`` λ_a, ``pressure`` p (MPa, the work-conjugate of the cavity volume),
``volume_ratio`` V/V₀ = λ_a³, ``outer_stretch`` λ_b (the chord of the outer-surface marks) and
``cap_force`` (the x resultant of the pressure on the octant's cavity wall, N).

Oracle (incompressible thick sphere, e.g. Ogden 1984 §5.3.2): with λ_b³ = 1 + (λ_a³ − 1) A³/B³,

    p(λ_a) = ∫_{λ_b}^{λ_a} Ŵ'(λ) / (λ³ − 1) dλ,   Ŵ(λ) = W(diag(λ, λ, λ⁻²)),

Ŵ' = 2 (P₁₁ − λ⁻³ P₃₃) of the model at that isochoric F; for Neo-Hookean
p = 2μ [(1/λ_b + 1/(4λ_b⁴)) − (1/λ_a + 1/(4λ_a⁴))]. A compressible FE model approaches it as
K/μ → ∞. The pressure maximum, where there is one, is a property of the specimen: results.json →
measured.limit_point (its pressure and stretch), never a solver failure (the thin-shell
Neo-Hookean balloon has it at λ = 7^(1/6)).
"""

from __future__ import annotations

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import PlotSpec, TestKind, relative_error, stretch_value


class Inflation(TestKind):
    name = "inflation"
    control_name = "inner hoop stretch"
    axes = (0,)
    oracle_setups = {"sphere-shell": "cavity"}
    symmetric = False  # the octant is built reduced already
    measures_E = False
    force_column, control_column = "cap_force", "stretch"
    plot = PlotSpec("stretch", "pressure", "inner hoop stretch λ_a [–]", "pressure p [MPa]",
                    (("stretch", "pressure", "pressure"),))
    measured_units = {"limit_point": "pressure MPa, stretch 1", "initial_slope": "MPa (dp/dλ_a at λ_a = 1)"}
    doc = "inflation of a spherical shell under volume control (through the pressure maximum)"
    readers = ("cavity-pressure",)  # vlab/measure/kinds.py
    fit = "inflation"
    option_keys = {"control": ("volume",)}
    units = {"stretch": "1 (inner surface, hoop)", "pressure": "MPa", "volume_ratio": "1 (cavity V / V0)",
             "outer_stretch": "1 (outer surface, hoop)", "cap_force": "N (octant cavity wall, x resultant)",
             "time": "s"}

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        field, v = t.field("stretch"), t.get("stretch")
        if isinstance(v, list):
            raise SceneError(f"{field} must be a single number (the inner hoop stretch) for kind = 'inflation', "
                             f"got {fields.show(v)}")
        lam = stretch_value(field, v)
        if lam <= 1.0:
            raise SceneError(f"{field} must be > 1 for kind = 'inflation' (allowed 1..10), got {lam:g}")
        return (lam,)

    def check(self, test, effects: dict) -> None:
        super().check(test, effects)
        if test.grips != "cavity":
            raise SceneError(f"test.grips must be 'cavity' for test.kind = 'inflation', got {test.grips!r}")

    def loading(self, specimen, X, test):
        from vlab.loading.inflation import inflation_loading

        return inflation_loading(specimen, X, test.targets[0])

    def isochoric(self, values):
        lam = values[0]
        return np.diag([lam, lam, lam**-2])  # the inner wall: equibiaxial, isochoric

    def areas(self, specimen) -> dict[int, float]:
        return {0: specimen.area0[0]}  # the octant's cavity volume V₀ (mm³): the pressure reader's

    def state(self, material, values):
        """The inner wall's state F = diag(λ, λ, λ⁻²) (what the admissibility check reads)."""
        from vlab.materials.homogeneous import HomogeneousState

        F = self.isochoric(values)
        P = np.asarray(material.stress(F), dtype=float)
        F.setflags(write=False)
        P.setflags(write=False)
        return HomogeneousState(F=F, P=P, lateral_stretch=float(values[0]) ** -2)

    def reference(self, material, curve) -> dict:
        from vlab.loading.thick_sphere import thick_sphere_pressure

        ratio = curve.extra["wall_ratio"][0] if curve.extra.get("wall_ratio") else None
        out = {"pressure": [thick_sphere_pressure(material, lam, ratio) for lam in curve.stretch[0]],
               "note": "incompressible thick sphere; the FE model is compressible (K/mu finite)"}
        out["max_relative_error_pressure"] = relative_error(curve.extra.get("pressure", []), out["pressure"])
        return out

    def columns(self, curve) -> dict[str, list[float]]:
        return {"stretch": list(curve.stretch[0]), "pressure": list(curve.extra.get("pressure", [])),
                "volume_ratio": [lam**3 for lam in curve.stretch[0]],
                "outer_stretch": [1.0 + e for e in curve.strain[0]], "cap_force": list(curve.force[0])}


INFLATION = Inflation()
