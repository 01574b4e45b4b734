"""Kind "free-end-torsion": the length change (and the torque) against the twist of a solid
incompressible cylinder of radius a whose end slides freely along the axis (the scene's
`[test] axial = "free"`): at each twist ψ (per undeformed length, rad/mm) the axial stretch λ is
the root of the axial force of vlab.identify.kinds.tension_torsion,

    N(ψ, λ) = 0,

and the torque is M(ψ, λ) at that root. For Neo-Hookean, N = π a² μ (λ − λ⁻²) − (π/4) μ ψ² a⁴/λ²
gives λ³ = 1 + (ψ a)²/4, independent of μ: the cylinder lengthens (Poynting), whatever the
modulus. For Mooney–Rivlin the length change separates C10 from C01, which the torque alone cannot.

The root is found per card and twist by Newton in complex arithmetic (as the free stretch of the
homogeneous kinds, vlab.identify.states): the slope ∂N/∂λ from a real difference quotient only
steers the iteration, and the converged complex root carries the card's complex step, so its
derivative is the implicit function theorem's ∂λ/∂c = −(∂N/∂c)/(∂N/∂λ), exact.

The fitted output is the axial strain λ − 1 (the relative residual of λ itself would weigh a
strain of 1e-3 as 1e-3 of the stretch); the column is ``axial_stretch`` λ.

Columns: ``twist`` ψ (rad/mm, strictly monotonic), ``axial_stretch`` λ, optional ``torque``
(``units``: N*mm or N*m); ``[data.geometry] radius`` a (mm).
"""

from __future__ import annotations

import numpy as np

from vlab.fields import SceneError
from vlab.identify.datasets import check_monotonic
from vlab.identify.kinds import torsion
from vlab.identify.kinds.base import FitKind
from vlab.identify.kinds.tension_torsion import STRETCH_RANGE, cylinder_loads, section_states, surface_I1

__all__ = ["KIND", "free_stretch"]

ITERATIONS = 60
WRONG_SIGN = 1e-3  # axial strain below −WRONG_SIGN: a free end that shortened


def free_stretch(model, X, twist, radius: float):
    """λ (m, n) with N(ψ, λ) = 0 at twists ψ (n,) of internal coordinates X (m, n_x); complex
    where X is (the derivative of the root in its imaginary part)."""
    X = np.asarray(X)
    lam = np.ones((X.shape[0], len(twist)), dtype=X.dtype if np.iscomplexobj(X) else float)

    def force(v):
        return cylinder_loads(model, X, twist, radius, v)[1]

    lo, hi = STRETCH_RANGE
    for _ in range(ITERATIONS):
        g = force(lam)
        real = np.real(lam)
        slope = (np.real(force(real * (1.0 + 1e-7))) - np.real(g)) / (real * 1e-7)  # Re g = N(Re λ) to O(h²)
        step = g / np.where(slope > 0, slope, np.nan)  # N falling with λ: no free length to find
        new = lam - step
        inside = (np.real(new) > lo) & (np.real(new) < hi)
        lam = np.where(inside, new, 0.5 * (lam + np.clip(np.real(new), lo, hi)))
        done = np.abs(step) <= 1e-14 * np.abs(lam)
        if np.all(done | np.isnan(step)):
            break
    return np.where(done, lam, np.nan)  # no root (a card far from the data's): the residual's 1e10


def predict(model, X, d):
    """Axial strain (and torque) of data set d: (m, n) or (m, 2n)."""
    radius = d.extra["geometry"]["radius"]
    lam = free_stretch(model, X, d.a, radius)
    if "torque" not in d.extra["outputs"]:
        return lam - 1.0
    return np.concatenate([lam - 1.0, cylinder_loads(model, X, d.a, radius, lam)[0]], axis=-1)


def build(path, cols, wanted, lines, factor, geometry):
    psi, lam = cols["twist"], cols["axial_stretch"]
    check_monotonic(path, wanted["twist"], psi, lines)
    bad = np.nonzero((lam < STRETCH_RANGE[0]) | (lam > STRETCH_RANGE[1]) | (lam - 1.0 < -WRONG_SIGN))[0]
    if len(bad):
        j = int(bad[0])
        raise SceneError(f"{path.name} row {int(lines[j])} column {wanted['axial_stretch']!r}: axial stretch "
                         f"{lam[j]:g} is not a free end's (a twisted free cylinder lengthens: {1 - WRONG_SIGN:g} <= "
                         f"stretch <= {STRETCH_RANGE[1]:g}; a strain column goes in as 1 + strain)")
    if "torque" not in cols:
        return psi, None, lam - 1.0, {"geometry": geometry, "outputs": ("axial_strain",)}
    torque = cols["torque"] * factor
    torsion.check_torque(path, wanted, psi, torque, lines, geometry["radius"])
    return psi, None, np.r_[lam - 1.0, torque], {"geometry": geometry, "outputs": ("axial_strain", "torque")}


def max_I1(d) -> float:
    """I1 at the surface at the data's own stretches (the largest shear)."""
    radius = d.extra["geometry"]["radius"]
    return float(np.max(surface_I1(d.a, radius, 1.0 + d.y[:len(d.a)])))


def states(d):
    """Along the radius at the data's own twists and measured stretches."""
    return section_states(d.a, d.extra["geometry"]["radius"], 1.0 + d.y[:len(d.a)])


KIND = FitKind(
    name="free-end-torsion", columns=(("twist", "axial_stretch"), ("torque",)), control="twist",
    geometry={"radius": "the cylinder's undeformed radius a"}, units={"N*mm": 1.0, "N*m": 1e3},
    default_unit="N*mm", measures=(), compressible=False, build=build, predict=predict, max_I1=max_I1,
    labels=("twist ψ (rad/mm, per undeformed length)", {"axial_strain": "axial strain λ − 1 (free end)",
                                                         "torque": "torque (N·mm)"}), states=states)
