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

The bulge test runs the same kind on a clamped ``membrane`` (vlab.geometry.membrane, grips
``clamped``): its load is ``volume_ratio`` v = (V₀ + V) / V₀, the liquid pumped into the chamber of
volume V₀ under the sheet (vlab.loading.bulge). Records per level: ``stretch`` (the pole's in-plane
stretch), ``pressure``, ``volume_ratio``, ``pole_height`` (mm), ``pole_stress`` (the lab's
p R_c / (2t)) and ``pole_stress_fe`` (the FE's), ``cap_force`` (N, z, the quarter's rim). Oracle: the
pole is in equibiaxial stretch, σ_eq(λ) = λ Ŵ'(λ) / 2 at the recorded pole stretch
(vlab.loading.thick_sphere.equibiaxial_stress), which both pole stresses approach as t/a → 0 and
the mesh is refined (tests/test_bulge.py states the study).
"""

from __future__ import annotations

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import LoadFromZero, PlotSpec, TestKind, relative_error, stretch_value

GROWTH = 2.0  # a bulge's first levels: each at most this factor above the one before
TRANSITION_HEIGHT = 10.0  # pole height, in sheet thicknesses, up to which a bulge's levels are halved


class Inflation(TestKind):
    name = "inflation"
    control_name = "inner hoop stretch"
    axes = (0,)
    oracle_setups = {"sphere-shell": "cavity", "membrane": "clamped"}
    symmetric = False  # the octant is built reduced already
    cyclic = True  # volume control: up and back down the same (elastic) curve
    measures_E = False
    force_column, control_column = "cap_force", "stretch"
    plot = PlotSpec("stretch", "pressure", "inner hoop stretch λ_a [–]", "pressure p [MPa]",
                    (("stretch", "pressure", "pressure"),))
    measured_units = {"limit_point": "pressure MPa, stretch 1", "initial_slope": "MPa (dp/dλ_a at λ_a = 1)"}
    doc = ("inflation of a spherical shell (a balloon) or of a clamped membrane (the bulge test) under volume "
           "control (through the pressure maximum)")
    extra_load_keys = ("volume_ratio", "pressure")
    readers = ("cavity-pressure",)  # vlab/measure/kinds.py
    fit = "inflation"
    option_keys = {"control": ("volume", "pressure")}
    units = {"stretch": "1 (inner surface, hoop)", "pressure": "MPa", "volume_ratio": "1 (cavity V / V0)",
             "outer_stretch": "1 (outer surface, hoop)", "cap_force": "N (octant cavity wall, x resultant)",
             "time": "s"}
    bulge_units = {"stretch": "1 (pole, in-plane, FE)", "pressure": "MPa (the liquid's)",
                   "volume_ratio": "1 ((V0 + V) / V0, V0 the chamber's liquid, V the bulge's)",
                   "pole_height": "mm (mid-surface)", "pole_stress": "MPa (lab: p R_c / (2 t))",
                   "pole_stress_fe": "MPa (FE: (s_xx + s_yy)/2 - s_zz at the pole)",
                   "cap_force": "N (the quarter's rim, z resultant)", "time": "s"}

    def units_of(self, columns: dict) -> dict[str, str]:
        return dict(self.bulge_units if "pole_height" in columns else self.units)

    def load_key_for(self, shape: str, options: dict[str, str]) -> str:
        """``pressure`` (MPa) under control = "pressure"; else a membrane's ``volume_ratio``, a
        sphere's ``stretch``."""
        if options.get("control") == "pressure":
            return "pressure"
        return "volume_ratio" if shape == "membrane" else "stretch"

    def control_label(self, test, shape: str) -> str:
        """The inner hoop stretch of a sphere, the pumped volume ratio of a membrane's chamber, or
        the pressure (MPa) under control = "pressure" (load_key_for)."""
        return {"pressure": "pressure (MPa)", "volume_ratio": "volume ratio"}.get(
            self.load_key_for(shape, dict(test.options)), self.control_name)

    def for_test(self, test) -> TestKind:
        return PRESSURE_INFLATION if test.option("control") == "pressure" else self

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        if "pressure" in t.raw:
            p = fields.number(t.field("pressure"), t.get("pressure"), note=" (MPa, > 0)")
            if not p > 0.0:
                raise SceneError(f"{t.field('pressure')} must be > 0 (MPa, the final pressure), got {p:g}")
            return (p,)
        key = "volume_ratio" if "volume_ratio" in t.raw else "stretch"  # the shape's (test.py checks which)
        what = "the pumped volume ratio" if key == "volume_ratio" else "the inner hoop stretch"
        field, v = t.field(key), t.get(key)
        if isinstance(v, list):
            raise SceneError(f"{field} must be a single number ({what}) for kind = 'inflation', got {fields.show(v)}")
        lam = stretch_value(field, v)
        if lam <= 1.0:
            raise SceneError(f"{field} must be > 1 for kind = 'inflation' (allowed 1..10), got {lam:g}")
        return (lam,)

    def check(self, test, effects: dict) -> None:
        super().check(test, effects)
        if test.protocol.name == "cyclic" and test.option("control") == "pressure":
            raise SceneError("test.protocol = 'cyclic' needs test.control = 'volume' for test.kind = 'inflation' "
                             "(a pressure cycle cannot pass the pressure maximum), got test.control = 'pressure'")
        if test.grips not in ("cavity", "clamped"):
            raise SceneError(f"test.grips must be 'cavity' (a sphere-shell) or 'clamped' (a membrane) for "
                             f"test.kind = 'inflation', got {test.grips!r}")

    def describe(self, values) -> str:
        return f"inflation control (stretch or volume ratio) {values[0]:.4g}"

    def loading(self, specimen, X, test):
        if specimen.shape == "membrane":
            from vlab.loading.bulge import bulge_loading

            return bulge_loading(specimen, X, test.option("control"), test.targets[0])
        from vlab.loading.inflation import inflation_loading, pressure_loading

        if test.option("control") == "pressure":
            return pressure_loading(specimen, X, test.targets[0])
        return inflation_loading(specimen, X, test.targets[0])

    def isochoric(self, values):
        lam = values[0]
        return np.diag([lam, lam, lam**-2])  # the inner wall: equibiaxial, isochoric

    def locking_path(self, test, specimen):
        """A sphere's inner wall, diag(λ, λ, λ⁻²) at the hoop stretch λ; a membrane's volume ratio v
        is not a stretch: its path is the equibiaxial stretch √A(v) of the least-area cap that
        holds the pumped volume (vlab.loading.bulge.cap_area_ratio), a lower bound of the bulge's
        worst state, so a test is refused only where the sheet surely locks."""
        key, path = super().locking_path(test, specimen)
        if specimen.shape != "membrane":
            return key, path
        from vlab.loading.bulge import cap_area_ratio

        return key, lambda s: self.isochoric([np.sqrt(cap_area_ratio(self.at(test.targets, s)[0]))])

    def scheduled(self, levels, test, specimen):
        """A membrane pumped under volume control leaves plate bending for membrane action while its
        pole rises through a few thicknesses t₀, and Newton needs 40–90 iterations and cutbacks
        to cross that from a bent plate in one level. Its monotonic schedule gains levels there:
        the first regular level t₁ over GROWTH^k (k = 1, 2, …) down to the modulus window's last
        level, and a midpoint in every regular interval that starts before the least-area cap of
        the pumped volume (vlab.loading.bulge.cap_area_ratio) reaches TRANSITION_HEIGHT × t₀."""
        if specimen.shape != "membrane" or test.option("control") != "volume" or test.protocol.name != "monotonic":
            return levels
        from vlab.loading.protocol import Levels

        t = np.asarray(levels.t, dtype=float)
        first = 1.0 / test.steps
        window = t[t < first * (1.0 - 1e-9)]
        floor = window.max() * np.sqrt(GROWTH) if window.size else 0.0
        extra = [x for x in first / GROWTH ** np.arange(1, 8) if x > floor]
        eta = TRANSITION_HEIGHT * specimen.thickness / specimen.radius  # the cap's height / a
        band = eta * (3.0 + eta * eta) / 6.0 / (test.targets[0] - 1.0)  # its load parameter: V = (v − 1) π a³
        extra += [(k + 0.5) * first for k in range(1, test.steps) if k * first < band]
        merged = np.unique(np.concatenate([t, extra]))
        return Levels(merged, None, np.zeros(len(merged), dtype=bool))

    def has_state(self, shape: str) -> bool:
        """A membrane's control is a volume ratio: no material state follows from it alone."""
        return shape != "membrane"

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

    @staticmethod
    def stretch(curve) -> list[float]:
        """The recorded stretch: a bulge's pole, a balloon's inner wall measured (pressure control)
        or prescribed (volume control)."""
        return list(curve.extra.get("pole_stretch") or curve.extra.get("inner_stretch") or curve.stretch[0])

    def reference(self, material, curve) -> dict:
        if "pole_stretch" in curve.extra:
            return self._membrane_reference(material, curve)
        from vlab.loading.thick_sphere import thick_sphere_pressure

        ratio = curve.extra["wall_ratio"][0] if curve.extra.get("wall_ratio") else None
        out = {"pressure": [thick_sphere_pressure(material, lam, ratio) for lam in self.stretch(curve)],
               "note": "incompressible thick sphere; the FE model is compressible (K/mu finite)"}
        out["max_relative_error_pressure"] = relative_error(curve.extra.get("pressure", []), out["pressure"])
        return out

    def _membrane_reference(self, material, curve) -> dict:
        """σ_eq at the recorded pole stretch (module docstring), and the largest relative
        deviation of the lab's and the FE's pole stress from it over the rows past the first
        tenth of the final pole strain (a flat sheet's pole is in bending, not in membrane action)."""
        from vlab.loading.thick_sphere import equibiaxial_stress

        lam = np.asarray(curve.extra["pole_stretch"], float)
        ref = np.array([equibiaxial_stress(material, x) for x in lam])
        out: dict = {"pole_stress": ref.tolist(), "note": "equibiaxial membrane stress at the FE pole stretch "
                     "(incompressible; the FE model is compressible, K/mu finite)"}
        rows = lam - 1.0 >= 0.1 * (lam[-1] - 1.0) if len(lam) else lam > 0
        for key in ("pole_stress", "pole_stress_fe"):
            if curve.extra.get(key) and np.any(rows):
                got = np.asarray(curve.extra[key], float)[rows]
                out[f"max_relative_error_{key}"] = float(np.max(np.abs(got / ref[rows] - 1.0)))
        return out

    def columns(self, curve) -> dict[str, list[float]]:
        if "pole_stretch" in curve.extra:
            return {"stretch": list(curve.extra["pole_stretch"])} | {
                key: list(curve.extra[key]) for key in ("pressure", "volume_ratio", "pole_height", "pole_stress",
                                                        "pole_stress_fe") if key in curve.extra} | {
                "cap_force": list(curve.force[0])}
        volume = curve.extra.get("volume_ratio") or [lam**3 for lam in curve.stretch[0]]
        return {"stretch": self.stretch(curve), "pressure": list(curve.extra.get("pressure", [])),
                "volume_ratio": list(volume),
                "outer_stretch": [1.0 + e for e in curve.strain[0]], "cap_force": list(curve.force[0])}


INFLATION = Inflation()


class PressureInflation(LoadFromZero, Inflation):
    """Inflation under ``control = "pressure"``: the control value is the pressure p(t) = t p*
    (MPa); the stretch is measured. There is no equilibrium past a pressure maximum: the test
    stops there, and the stop says so (vlab.measure.inflation.pressure_maximum_reason)."""

    def describe(self, values) -> str:
        return f"pressure {values[0]:.4g} MPa"

    def isochoric(self, values):
        return np.eye(3)  # the stretch a pressure reaches is not known before the solve


PRESSURE_INFLATION = PressureInflation()
