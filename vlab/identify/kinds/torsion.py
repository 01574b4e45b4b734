"""Kind "torsion": torque and axial force against the twist of a solid incompressible cylinder of
radius a, its length held (Rivlin 1948; Ogden, Non-linear Elastic Deformations, §5.3).

The cylinder's state is r = R, θ = Θ + ψZ, z = Z: at radius r a simple shear γ = ψ r in the θ–z
plane (shear along θ, planes normal to z). With that simple shear's shear stress T(γ) and normal
stress differences N1(γ) = σθθ − σrr, N2(γ) = σzz − σrr, radial equilibrium with σrr(a) = 0 gives

    torque       M = 2π ∫_0^a T(ψr) r² dr                       (N·mm for MPa, mm)
    axial force  N = 2π ∫_0^a (N2 − N1/2)(ψr) r dr              (N; < 0: the Poynting push)

(∫ σrr r dr = −½ ∫ N1 r dr by parts). In principal stretches λ± = √(1 + γ²/4) ± γ/2, λ3 = 1, with
w_i the law's principal Kirchhoff stresses and cos 2θ = γ/√(4 + γ²) the angle of B's axes:
T = (w₊ − w₋)/√(4 + γ²), N1 = w₊ cos²θ + w₋ sin²θ − w₃, N2 = w₊ sin²θ + w₋ cos²θ − w₃. For
Mooney–Rivlin (T = 2(C10 + C01)γ, N1 = 2C10γ², N2 = −2C01γ²) these are Rivlin's
M = π ψ a⁴ (C10 + C01) and N = −(π/2) ψ² a⁴ (C10 + 2 C01), for every law they are Gauss–Legendre
sums over r (``NODES`` points: exact for a polynomial energy). A compressible card enters by its
isochoric law (the incompressible cylinder: J = 1, no bulk term).

Columns: ``twist`` ψ (rad/mm, strictly monotonic), ``torque`` (``units``: N*mm or N*m) and,
optionally, ``axial_force`` (N, tension > 0); ``[data.geometry] radius`` (mm).
"""

from __future__ import annotations

import numpy as np

from vlab.fields import SceneError
from vlab.identify.datasets import STRESS_RANGE, check_monotonic
from vlab.identify.kinds.base import FitKind, gauss

__all__ = ["KIND", "check_torque", "shear_functions", "torque_and_force"]

NODES = 32
WRONG_SIGN = 0.02


def shear_functions(model, c, g):
    """(T, N1, N2) of the simple shear γ = g (arrays broadcast with the card values c), MPa."""
    lp = np.sqrt(1.0 + 0.25 * g * g) + 0.5 * g
    w = model.law.w(c, lp, 1.0 + 0.0 * g, 1.0 / lp)
    root = np.sqrt(4.0 + g * g)
    cos2 = 0.5 * (1.0 + g / root)          # cos²θ of the larger axis of B with the shear direction
    sin2 = 1.0 - cos2
    return (w[0] - w[2]) / root, w[0] * cos2 + w[2] * sin2 - w[1], w[0] * sin2 + w[2] * cos2 - w[1]


def torque_and_force(model, X, twist, radius: float):
    """(M, N): (m, n) each, N·mm and N, at twists ψ (n,) rad/mm of internal coordinates X (m, n_x)."""
    c, _ = model.split(np.asarray(X)[:, None, :])
    s, w = gauss(NODES)
    psi = np.asarray(twist, float)
    g = (psi[:, None] * radius * s[None, :]).reshape(1, -1)  # γ at r = a s, flattened (1, n q)
    T, N1, N2 = shear_functions(model, c, g)
    m = np.asarray(X).shape[0]
    shape = (m, len(psi), NODES)
    M = 2.0 * np.pi * radius**3 * (np.broadcast_to(T, (m, g.shape[1])).reshape(shape) @ (w * s * s))
    N = 2.0 * np.pi * radius**2 * (np.broadcast_to(N2 - 0.5 * N1, (m, g.shape[1])).reshape(shape) @ (w * s))
    return M, N


def predict(model, X, d):
    """Torque (and axial force) of data set d: (m, n) or (m, 2n)."""
    M, N = torque_and_force(model, X, d.a, d.extra["geometry"]["radius"])
    return np.concatenate([M, N], axis=-1) if "axial_force" in d.extra["outputs"] else M


def check_torque(path, wanted, psi, torque, lines, radius: float) -> None:
    """The torque's size (as the surface shear stress 2M/(πa³), MPa) within STRESS_RANGE, and its
    sign that of the twist."""
    tau = 2.0 * np.abs(torque) / (np.pi * radius**3)
    top = float(np.max(tau))
    lo, hi = STRESS_RANGE
    if not lo <= top <= hi:
        j = int(np.argmax(tau))
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted['torque']!r}: the surface shear stress "
                         f"2M/(πa³) = {top:g} MPa is outside the plausible range {lo:g}..{hi:g} MPa (check "
                         "data[].units, N*mm or N*m, and geometry.radius, mm)")
    bad = np.nonzero(np.sign(psi) * torque < -WRONG_SIGN * float(np.max(np.abs(torque))))[0]
    if len(bad):
        j = int(bad[0])
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted['torque']!r}: torque {torque[j]:g} at "
                         f"twist {psi[j]:g} has the sign opposite to the twist (check the sign convention)")


def build(path, cols, wanted, lines, factor, geometry):
    psi, torque = cols["twist"], cols["torque"] * factor
    check_monotonic(path, wanted["twist"], psi, lines)
    check_torque(path, wanted, psi, torque, lines, geometry["radius"])
    outputs = ("torque", "axial_force") if "axial_force" in cols else ("torque",)
    y = np.r_[torque, cols["axial_force"]] if "axial_force" in cols else torque
    return psi, None, y, {"geometry": geometry, "outputs": outputs}


def max_I1(d) -> float:
    """I1 = 3 + (ψ a)² at the surface, the largest shear."""
    return 3.0 + float(np.max(np.abs(d.a))) ** 2 * d.extra["geometry"]["radius"] ** 2


def states(d):
    """Simple shears ψ r along the radius (λ = 1 of the stretched cylinder's states)."""
    from vlab.identify.kinds.tension_torsion import section_states  # (it builds on this module)
    return section_states(d.a, d.extra["geometry"]["radius"], 1.0)


KIND = FitKind(
    name="torsion", columns=(("twist", "torque"), ("axial_force",)), control="twist",
    geometry={"radius": "the cylinder's radius a"}, units={"N*mm": 1.0, "N*m": 1e3}, default_unit="N*mm",
    measures=(), compressible=False, build=build, predict=predict, max_I1=max_I1,
    labels=("twist ψ (rad/mm)", {"torque": "torque (N·mm)", "axial_force": "axial force (N)"}), states=states)
