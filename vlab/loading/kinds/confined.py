"""Confined compression in a frictionless rigid die: ``stretch = λ`` (one number, 0.2 ≤ λ < 1).

The specimen (a cylinder, or a block) sits in a rigid die that holds its lateral surface and is
compressed along x between frictionless platens (vlab.loading.die). The homogeneous state is
F = diag(λ, 1, 1), J = λ: the oracle, with the axial nominal stress P₁₁ and the pressure
p = −tr σ / 3 (σ = P Fᵀ / J) of the material at that F, for every model. It is the volumetric
test: E and ν do not show on their own; the initial slopes give (measure/confined.py)

    M = dP₁₁/dε = K + 4G/3   (the constrained, or P-wave, modulus; ε = λ − 1)
    K = −dp/d(J − 1)         (the bulk modulus)

over the modulus window. Records per level: the platen stretch λ, the axial nominal stress F/A₀,
the volume ratio J = ∫ det F dV / V₀ and the pressure p over the body (FE field averages).
"""

from __future__ import annotations

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds.base import PlotSpec, TestKind, relative_error, stretch_value

PLATEN_DEPTH = 0.08  # a platen's thickness in the renders, per specimen length
DIE_GAP = 0.02  # the drawn die wall's clearance, per section size (the bore itself is the specimen's)
DIE_OPACITY = 0.22  # the die's wall is drawn see-through: the specimen inside shows


class ConfinedCompression(TestKind):
    name = "confined-compression"
    control_name = "platen stretch"
    axes = (0,)
    oracle_setups = {"cylinder": "die", "block": "die"}
    symmetric = False
    measures_E = False
    plot = PlotSpec("stretch", "stress", "platen stretch λ [–]", "axial nominal stress F/A₀ [MPa]",
                    (("stretch", "stress", "stress_x"),))
    measured_units = {"bulk_modulus": "MPa", "constrained_modulus": "MPa"}
    doc = "confined compression in a frictionless rigid die: F = diag(λ, 1, 1)"
    readers = ("volume-pressure",)  # vlab/measure/kinds.py
    fit = "confined"
    units = {"stretch": "1 (platen)", "strain": "1 (extensometer, engineering)",
             "stress": "MPa (axial, engineering: F / A0)", "force": "N", "volume_ratio": "1 (FE: V / V0)",
             "pressure": "MPa (FE: -tr(sigma)/3, volume average)", "time": "s"}

    def parse_load(self, t: fields.Table, protocol: str) -> tuple[float, ...]:
        field, v = t.field("stretch"), t.get("stretch")
        if isinstance(v, list):
            raise SceneError(f"{field} must be a single number for kind = 'confined-compression', got "
                             f"{fields.show(v)}")
        lam = stretch_value(field, v)
        if lam >= 1.0:
            raise SceneError(f"{field} must be < 1 for kind = 'confined-compression' (a die compresses; "
                             f"allowed 0.2..1), got {lam:g}")
        return (lam,)

    def check(self, test, effects: dict) -> None:
        super().check(test, effects)
        if test.grips != "die":
            raise SceneError(f"test.grips must be 'die' for test.kind = 'confined-compression', got {test.grips!r}")

    def loading(self, specimen, X, test):
        from vlab.loading.die import die_loading

        return die_loading(specimen, X, test.targets[0])

    def fixtures(self, specimen) -> tuple:
        """The die (see-through: its bore, a tube r = a about the cylinder's axis, or the block's four
        side walls) and the two platens (discs or plates of the section, PLATEN_DEPTH × L thick),
        the one on x = L bonded to that end face; the die runs on past both platens. Its wall is
        drawn DIE_GAP of the section outside the specimen's surface, which it would otherwise
        cover pixel for pixel."""
        from vlab.geometry import fixtures as fx

        X = specimen.mesh.p.T
        lo, hi = X.min(axis=0), X.max(axis=0)
        depth = PLATEN_DEPTH * (hi[0] - lo[0])
        tol = 1e-9 * specimen.length_scale
        ends = ((lo[0] - depth, lo[0], lambda P: np.abs(P[:, 0] - lo[0]) <= tol),
                (hi[0], hi[0] + depth, lambda P: np.abs(P[:, 0] - hi[0]) <= tol))
        if specimen.shape == "cylinder":
            centre, radius = 0.5 * (lo[1:] + hi[1:]), 0.5 * float(hi[1] - lo[1])
            wall = fx.tube(lo[0] - 2 * depth, hi[0] + 2 * depth, centre, (1.0 + DIE_GAP) * radius)
            plates = [fx.disc(a, b, centre, radius) for a, b, _ in ends]
        else:
            gap = DIE_GAP * (hi - lo)
            wall = fx.square_tube((lo[0] - 2 * depth, lo[1] - gap[1], lo[2] - gap[2]),
                                  (hi[0] + 2 * depth, hi[1] + gap[1], hi[2] + gap[2]))
            plates = [fx.box((a, lo[1], lo[2]), (b, hi[1], hi[2])) for a, b, _ in ends]
        return (fx.Part("die", *wall, None, fx.DIE_COLOUR, DIE_OPACITY),
                fx.Part("fixed platen", *plates[0], ends[0][2], fx.PLATEN_COLOUR),
                fx.Part("moving platen", *plates[1], ends[1][2], fx.PLATEN_COLOUR))

    def isochoric(self, values):
        return np.eye(3)  # the die's state changes only the volume: no isochoric part to lock

    def state(self, material, values):
        from vlab.materials.homogeneous import HomogeneousState

        F = np.diag([float(values[0]), 1.0, 1.0])
        P = np.asarray(material.stress(F), dtype=float)
        F.setflags(write=False)
        P.setflags(write=False)
        return HomogeneousState(F=F, P=P, lateral_stretch=1.0)

    def reference(self, material, curve) -> dict:
        states = [self.state(material, (lam,)) for lam in curve.stretch[0]]
        out = {"stress_x": [float(s.P[0, 0]) for s in states],
               "pressure": [float(-np.trace(s.cauchy) / 3.0) for s in states],
               "volume_ratio": [float(s.F[0, 0]) for s in states]}
        out["max_relative_error_x"] = relative_error(curve.column("stress", 0), out["stress_x"])
        out["max_relative_error_pressure"] = relative_error(curve.extra.get("pressure", []), out["pressure"])
        out["max_error_volume_ratio"] = (float(np.max(np.abs(np.subtract(curve.extra["volume_ratio"],
                                                                         out["volume_ratio"]))))
                                         if curve.extra.get("volume_ratio") else None)
        return out

    def columns(self, curve) -> dict[str, list[float]]:
        return {"stretch": list(curve.stretch[0]), "strain": list(curve.strain[0]),
                "stress": list(curve.column("stress", 0)), "force": list(curve.force[0]),
                "volume_ratio": list(curve.extra.get("volume_ratio", [])),
                "pressure": list(curve.extra.get("pressure", []))}


CONFINED = ConfinedCompression()
