"""Exact homogeneous states of a block with roller grips and free lateral faces.

These are the test oracles for the finite-element solver: a block stretched by frictionless
grips deforms homogeneously, so the stress–stretch curve follows from one scalar equation.

- Uniaxial: F = diag(λ, t, t) with the lateral stretch t > 0 solving P₂₂(F) = 0 (by isotropy
  P₃₃ = P₂₂); the nominal (engineering) stress is P₁₁.
- Biaxial: F = diag(λx, λy, t) with P₃₃(F) = 0.
- Planar (pure shear): F = diag(λ, 1, t) with P₃₃(F) = 0, the biaxial state at (λ, 1).
- Simple shear: F = I + γ e₁⊗e₂ prescribed on the whole boundary, nothing to solve.

The root is found with Brent's bracketing solver (:mod:`vlab.materials.brent`, the algorithm of
``scipy.optimize.brentq``) on g(t) = P_free(t)/t, starting from t = 1 and expanding the bracket
geometrically. For the four built-in models
the root is unique on t > 0 (so it is the branch through t = 1 at λ = 1):

- linear:          λ_L(λ − 1 + 2(t − 1)) + 2μ(t − 1) = 0        (always solvable)
- stvk:            t² = 1 − ν(λ² − 1)                           (only for λ² < 1 + 1/ν)
- stvk-volumetric: 2ηλ(λt² − 1) + μ(t² − 1) = 0, η = λ_L/2      (always solvable)
- neo-hookean:     μ(t² − 1) + λ_L ln(λt²) = 0                  (always solvable)

Plane strain (a sheet held at constant thickness, F₃₃ = 1): uniaxial F = diag(λ, t, 1) with
P₂₂ = 0, biaxial F = diag(λx, λy, 1) (nothing to solve). Plane stress needs no oracle of its own:
its free faces carry no stress, so it is the 3D uniaxial/biaxial state above.

(λ_L is the Lamé constant, λ the stretch.) If no positive root exists, InadmissibleState is
raised; its message always contains "no admissible state beyond stretch".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from vlab.materials.brent import brent_root

__all__ = ["InadmissibleState", "HomogeneousState", "uniaxial", "biaxial", "plane_strain_uniaxial",
           "plane_strain_biaxial", "homogeneous_uniaxial", "homogeneous_biaxial", "planar", "simple_shear",
           "isochoric_path_limit"]

_T_MIN = 1e-6      # smallest lateral stretch searched
_T_MAX = 1e6       # largest lateral stretch searched
_XTOL = 1e-15
_RTOL = 4.0 * np.finfo(float).eps


class InadmissibleState(ValueError):
    """No homogeneous equilibrium with a positive lateral stretch exists."""


@dataclass(frozen=True, eq=False)
class HomogeneousState:
    """A homogeneous equilibrium state.

    ``F``: (3,3) deformation gradient (diagonal), ``P``: (3,3) first Piola–Kirchhoff stress in
    MPa (zero on the free faces), ``lateral_stretch``: the solved free stretch t.
    Arrays are read-only.
    """

    F: np.ndarray
    P: np.ndarray
    lateral_stretch: float

    @property
    def nominal_stress(self) -> float:
        """Nominal (engineering) stress along x, P[0, 0], MPa."""
        return float(self.P[0, 0])

    @property
    def cauchy(self) -> np.ndarray:
        """True (Cauchy) stress σ = P Fᵀ / J, (3,3), MPa."""
        return self.P @ self.F.T / np.linalg.det(self.F)


def _free_residual(material, diag_of_t: Callable[[float], tuple], idx: int) -> Callable[[float], float]:
    def g(t: float) -> float:
        F = np.diag(diag_of_t(t))
        return float(material.stress(F)[idx, idx]) / t

    return g


def _bracket(g: Callable[[float], float], starts: tuple[float, ...] = (1.0,)) -> tuple[float, float] | None:
    """Bracket the root of g on (T_MIN, T_MAX) from the first start where g is finite (t = 1,
    else e.g. the pure dilatation, where a locking model is always admissible), expanding
    geometrically; where g stops being finite (a locking limit) the edge is bisected for the
    last finite value of the other sign. None if there is no root."""
    for t0 in starts:
        g0 = g(t0)
        if g0 == 0.0:
            return (t0, t0)
        if np.isfinite(g0):
            break
    else:
        return None
    sign = 1.0 if g0 > 0.0 else -1.0   # > 0: lateral faces pulled at t0, the root is below
    good, t = t0, t0 * (0.5 if sign > 0 else 2.0)
    while _T_MIN <= t <= _T_MAX:
        v = g(t)
        if not np.isfinite(v):
            found = _edge(g, good, t, sign)
            return None if found is None else tuple(sorted((found, good)))
        if sign * v < 0.0:
            return tuple(sorted((t, good)))
        good, t = t, t * (0.5 if sign > 0 else 2.0)
    return None


def _edge(g: Callable[[float], float], good: float, bad: float, sign: float) -> float | None:
    """Between ``good`` (g finite, sign ``sign``) and ``bad`` (g not finite): a t with finite g
    of the opposite sign, found by geometric bisection, or None."""
    for _ in range(200):
        m = np.sqrt(good * bad)
        v = g(m)
        if np.isfinite(v) and sign * v < 0.0:
            return float(m)
        if np.isfinite(v):
            good = m
        else:
            bad = m
        if abs(np.log(good / bad)) < 1e-15:
            return None
    return None


def _solve(g: Callable[[float], float], starts: tuple[float, ...] = (1.0,)) -> float | None:
    br = _bracket(g, starts)
    if br is None:
        return None
    lo, hi = br
    if lo == hi:
        return lo
    return brent_root(g, lo, hi, xtol=_XTOL, rtol=_RTOL, maxiter=500)


def _limit_along(admissible: Callable[[float], bool]) -> float:
    """Largest s in [0, 1] with ``admissible(s)`` (bisection; s = 0 is the unloaded state)."""
    a, b = 0.0, 1.0
    if not admissible(a):
        return a
    for _ in range(60):
        m = 0.5 * (a + b)
        if admissible(m):
            a = m
        else:
            b = m
        if b - a <= 1e-13:
            break
    return 0.5 * (a + b)


def _describe(material) -> str:
    nu = getattr(material, "poisson_ratio", None)
    name = getattr(material, "name", type(material).__name__)
    note = material.locking_note  # e.g. Gent: where the chains lock (vlab.materials.capabilities)
    text = f"{name} with nu={nu:.4g}" if nu is not None else str(name)
    return f"{text}; {note}" if note else text


def _check_stretch(value: float, label: str) -> float:
    value = float(value)
    if not (np.isfinite(value) and value > 0.0):
        raise ValueError(f"{label} must be a finite positive number, got {value}")
    return value


def _state(material, diag: tuple, t: float) -> HomogeneousState:
    F = np.diag(np.asarray(diag, dtype=float))
    P = np.asarray(material.stress(F), dtype=float)
    F.setflags(write=False)
    P.setflags(write=False)
    return HomogeneousState(F=F, P=P, lateral_stretch=float(t))


def uniaxial(material, stretch: float) -> HomogeneousState:
    """Uniaxial state F = diag(stretch, t, t) with P₂₂ = P₃₃ = 0, t > 0.

    Raises InadmissibleState if no positive lateral stretch gives equilibrium (e.g. StVK beyond
    stretch √(1 + 1/ν)), ValueError if ``stretch`` is not a finite positive number.
    """
    lam = _check_stretch(stretch, "stretch")
    t = _solve(_free_residual(material, lambda t: (lam, t, t), 1), (1.0, lam))
    if t is None:
        def ok(s: float) -> bool:
            ls = 1.0 + s * (lam - 1.0)
            return _bracket(_free_residual(material, lambda t: (ls, t, t), 1), (1.0, ls)) is not None

        lim = 1.0 + _limit_along(ok) * (lam - 1.0)
        raise InadmissibleState(
            f"no admissible state beyond stretch {lim:.6g} for {_describe(material)} "
            f"(requested stretch {lam:.6g}): free lateral faces have no equilibrium "
            f"(no lateral stretch t > {_T_MIN:g} makes P22 = 0)"
        )
    return _state(material, (lam, t, t), t)


def biaxial(material, stretch_x: float, stretch_y: float) -> HomogeneousState:
    """Biaxial state F = diag(stretch_x, stretch_y, t) with P₃₃ = 0, t > 0.

    Raises InadmissibleState if no positive thickness stretch gives equilibrium; the reported
    limit is on the straight path from (1, 1) to the requested stretches.
    """
    lx = _check_stretch(stretch_x, "stretch_x")
    ly = _check_stretch(stretch_y, "stretch_y")
    t = _solve(_free_residual(material, lambda t: (lx, ly, t), 2), (1.0, np.sqrt(lx * ly)))
    if t is None:
        def ok(s: float) -> bool:
            sx, sy = 1.0 + s * (lx - 1.0), 1.0 + s * (ly - 1.0)
            return _bracket(_free_residual(material, lambda t: (sx, sy, t), 2), (1.0, np.sqrt(sx * sy))) is not None

        s_lim = _limit_along(ok)
        lim_x, lim_y = 1.0 + s_lim * (lx - 1.0), 1.0 + s_lim * (ly - 1.0)
        raise InadmissibleState(
            f"no admissible state beyond stretch ({lim_x:.6g}, {lim_y:.6g}) "
            f"(requested ({lx:.6g}, {ly:.6g}), along the straight path from (1, 1)) "
            f"for {_describe(material)}: the free face has no equilibrium "
            f"(no thickness stretch t > {_T_MIN:g} makes P33 = 0)"
        )
    return _state(material, (lx, ly, t), t)


def plane_strain_uniaxial(material, stretch: float) -> HomogeneousState:
    """Plane-strain uniaxial state F = diag(stretch, t, 1) with P₂₂ = 0, t > 0 (InadmissibleState
    if none)."""
    lam = _check_stretch(stretch, "stretch")
    t = _solve(_free_residual(material, lambda t: (lam, t, 1.0), 1), (1.0, lam))
    if t is None:
        raise InadmissibleState(
            f"no admissible state beyond stretch {lam:.6g} (or below) for {_describe(material)} in "
            f"plane strain: no lateral stretch t > {_T_MIN:g} makes P22 = 0")
    return _state(material, (lam, t, 1.0), t)


def plane_strain_biaxial(material, stretch_x: float, stretch_y: float) -> HomogeneousState:
    """Plane-strain biaxial state F = diag(stretch_x, stretch_y, 1); lateral_stretch is 1."""
    lx = _check_stretch(stretch_x, "stretch_x")
    ly = _check_stretch(stretch_y, "stretch_y")
    return _state(material, (lx, ly, 1.0), 1.0)


def _plane(material):
    """(3D base law, "stress" | "strain" | "") of a material or of a 2D reduction of one
    (vlab.materials.plane: ``base`` and ``plane``)."""
    return (material.base if material.plane else material), material.plane


def homogeneous_uniaxial(material, stretch: float) -> HomogeneousState:
    """The roller-grip uniaxial state of a 3D material or of its plane reduction (plane stress:
    the 3D state, its free faces carry no stress; plane strain: F₃₃ = 1)."""
    base, plane = _plane(material)
    return plane_strain_uniaxial(base, stretch) if plane == "strain" else uniaxial(base, stretch)


def homogeneous_biaxial(material, stretch_x: float, stretch_y: float) -> HomogeneousState:
    """The roller-grip biaxial state of a 3D material or of its plane reduction."""
    base, plane = _plane(material)
    if plane == "strain":
        return plane_strain_biaxial(base, stretch_x, stretch_y)
    return biaxial(base, stretch_x, stretch_y)


def planar(material, stretch: float) -> HomogeneousState:
    """Pure shear (planar tension): F = diag(λ, 1, t), the lateral stretch held at 1 by the grips
    and the thickness free, P₃₃ = 0 — the biaxial state at (λ, 1). Nominal stress P₁₁; the lateral
    grips carry P₂₂ (≠ 0). On a 2D reduction: plane stress is this state, plane strain diag(λ, 1, 1).

    Incompressible Neo-Hookean (t = 1/λ): P₁₁ = μ (λ − λ⁻³)."""
    return homogeneous_biaxial(material, stretch, 1.0)


def simple_shear(material, gamma: float) -> HomogeneousState:
    """Simple shear x = X + γ Y e₁ imposed on the whole boundary: F = I + γ e₁⊗e₂ (J = 1), nothing
    to solve. P = P(F); the Cauchy stress σ = P Fᵀ/J carries the Poynting normal stresses, even in
    γ, beside the shear stress σ₁₂, odd in γ. Compressible Neo-Hookean (ψ = μ/2 (I₁ − 3) − μ ln J
    + λ_L/2 ln² J): σ = μ (B − I), so σ₁₂ = μ γ, σ₁₁ = μ γ², σ₂₂ = σ₃₃ = 0 and σ₁₁ − σ₂₂ = μ γ²
    (the incompressible result, since J = 1 here). ``lateral_stretch`` is 1 (no free stretch)."""
    gamma = float(gamma)
    if not np.isfinite(gamma):
        raise ValueError(f"gamma must be finite, got {gamma}")
    F = np.eye(3)
    F[0, 1] = gamma
    base, plane = _plane(material)
    if plane:
        raise ValueError("simple shear is a 3D state in vlab (F = I + γ e1⊗e2 on a block)")
    P = np.asarray(base.stress(F), dtype=float)
    F.setflags(write=False)
    P.setflags(write=False)
    return HomogeneousState(F=F, P=P, lateral_stretch=1.0)


def isochoric_path_limit(material, path) -> float | None:
    """The fraction s of a test's isochoric path ``path(s) -> F`` (3, 3), s in [0, 1] from the
    unloaded state to the target (the test kind's: vlab.loading.kinds ``isochoric``, e.g.
    diag(λ, λ^(−1/2), λ^(−1/2)) uniaxially), where the isochoric energy first becomes infinite
    (a locking limit: Gent's Ī₁ − 3 = Jm); None if the whole path is admissible."""
    def ok(s: float) -> bool:
        return bool(np.isfinite(material.isochoric_energy(np.asarray(path(s))[..., None])[0]))

    return None if ok(1.0) else _limit_along(ok)
