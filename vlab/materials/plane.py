"""Plane stress and plane strain for any vlab material: a 2D law on the in-plane deformation.

A thin sheet in the (x, y) plane carries no stress through its thickness. With the in-plane
deformation gradient F̄ (2×2) the full gradient is

    F(λ₃) = [[F̄, 0], [0, λ₃]]                  (no out-of-plane shear, by symmetry)

and the out-of-plane stretch λ₃ > 0 is fixed at every quadrature point by

    plane stress:  P₃₃(F(λ₃)) = 0              (solved here, see ``PlaneStress``)
    plane strain:  λ₃ = 1                      (a sheet held at constant thickness)

The 2D law is then, per unit reference VOLUME (the sheet thickness enters the integration
measure, vlab.fe.space):

    ψ̄(F̄)      = ψ(F(λ₃))                                               MPa
    P̄_αβ      = P_αβ(F(λ₃))           (∂ψ/∂λ₃ = P₃₃ = 0, so no extra term)     MPa
    Ā_αβγδ    = A_αβγδ − A_αβ33 A_33γδ / A_3333   (plane stress; static condensation of
                                                 dλ₃/dF̄_γδ = −A_33γδ / A_3333)   MPa
    Ā_αβγδ    = A_αβγδ                                                  (plane strain)

Greek indices run over 1, 2. The local solve is a vectorised Newton iteration on P₃₃(λ₃) = 0 over
all points at once, warm-started from the previous call; points where Newton fails (a step to
λ₃ ≤ 0, a non-positive slope A₃₃₃₃, no convergence) fall back to bracketing and safeguarded
bisection. Where no root λ₃ ∈ [1e-6, 1e6] exists (e.g. St. Venant–Kirchhoff stretched beyond
its limit, where S₃₃ > 0 for every λ₃) the energy is +inf (an inadmissible state for the
solver's line search) and ``out_of_plane_stretch`` raises :class:`PlaneStressError`.
"""

from __future__ import annotations

import numpy as np

from vlab.materials.capabilities import LawCapabilities

__all__ = ["PlaneStressError", "PlaneStress", "PlaneStrain", "plane_model", "embed"]

LAMBDA3_MIN, LAMBDA3_MAX = 1e-6, 1e6  # search range of the out-of-plane stretch
NEWTON_ITERATIONS = 25
NEWTON_STEP_TOL = 1e-11  # |Δλ₃| / λ₃ after which one more quadratic step is below round-off
BISECTION_ITERATIONS = 200


class PlaneStressError(ValueError):
    """No out-of-plane stretch λ₃ > 0 makes P₃₃ = 0 at some points."""


def embed(F2: np.ndarray, lambda3) -> np.ndarray:
    """The 3D gradient [[F̄, 0], [0, λ₃]] (3,3,*batch) from F̄ (2,2,*batch) and λ₃ (*batch)."""
    F2 = np.asarray(F2, dtype=float)
    if F2.ndim < 2 or F2.shape[:2] != (2, 2):
        raise ValueError(f"expected an in-plane gradient of shape (2, 2, *batch), got {F2.shape}")
    F3 = np.zeros((3, 3) + F2.shape[2:])
    F3[:2, :2] = F2
    F3[2, 2] = lambda3
    return F3


class _PlaneModel(LawCapabilities):
    """Shared by both 2D reductions: names and constants are the wrapped 3D model's."""

    plane = ""

    def __init__(self, base):
        self.base = base

    name = property(lambda self: self.base.name)
    is_linear = property(lambda self: self.base.is_linear)
    lmbda = property(lambda self: self.base.lmbda)
    mu = property(lambda self: self.base.mu)
    youngs_modulus = property(lambda self: self.base.youngs_modulus)
    poisson_ratio = property(lambda self: self.base.poisson_ratio)

    def out_of_plane_stretch(self, F2) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def full_gradient(self, F2) -> np.ndarray:
        """F(λ₃) (3,3,*batch) of in-plane gradients F̄ (2,2,*batch)."""
        return embed(F2, self.out_of_plane_stretch(F2))

    def stress(self, F2) -> np.ndarray:
        """P̄_αβ = P_αβ(F(λ₃)), shape (2,2,*batch), MPa."""
        return self.base.stress(self.full_gradient(F2))[:2, :2]

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.base!r})"


class PlaneStrain(_PlaneModel):
    """λ₃ = 1: the 3D law restricted to in-plane deformations."""

    plane = "strain"

    def out_of_plane_stretch(self, F2) -> np.ndarray:
        return np.ones(np.shape(F2)[2:])

    def energy(self, F2) -> np.ndarray:
        """ψ(F(1)), shape (*batch), MPa."""
        return self.base.energy(self.full_gradient(F2))

    def tangent(self, F2) -> np.ndarray:
        """A_αβγδ(F(1)), shape (2,2,2,2,*batch), MPa."""
        return self.base.tangent(self.full_gradient(F2))[:2, :2, :2, :2]


class PlaneStress(_PlaneModel):
    """P₃₃ = 0 through the thickness: λ₃ solved per point (see the module docstring)."""

    plane = "stress"

    def __init__(self, base):
        super().__init__(base)
        self._last: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # (F̄, λ₃, ok), flat

    # --- the 2D law ------------------------------------------------------------------------
    def out_of_plane_stretch(self, F2) -> np.ndarray:
        """λ₃ > 0 with P₃₃ = 0 at every point, shape (*batch); PlaneStressError if none exists."""
        lam, ok = self._solve(F2)
        if not ok.all():
            bad = np.flatnonzero(~ok.ravel())
            raise PlaneStressError(
                f"plane stress: no out-of-plane stretch λ₃ in [{LAMBDA3_MIN:g}, {LAMBDA3_MAX:g}] makes "
                f"P33 = 0 at {len(bad)} of {ok.size} point(s) (first: flat index {bad[0]}) for "
                f"{self.base.name} with nu={self.base.poisson_ratio:.4g}; the in-plane stretch is "
                f"beyond the model's admissible range")
        return lam

    def energy(self, F2) -> np.ndarray:
        """ψ(F(λ₃)), shape (*batch), MPa; +inf where no λ₃ exists (an inadmissible state)."""
        lam, ok = self._solve(F2)
        psi = np.asarray(self.base.energy(embed(F2, np.where(ok, lam, 1.0))), dtype=float)
        return np.where(ok, psi, np.inf)

    def tangent(self, F2) -> np.ndarray:
        """Ā = A_αβγδ − A_αβ33 A_33γδ / A_3333 at F(λ₃), shape (2,2,2,2,*batch), MPa."""
        A = self.base.tangent(self.full_gradient(F2))
        condensed = A[:2, :2, :2, :2] - (A[:2, :2, None, None, 2, 2] * A[None, None, 2, 2, :2, :2]
                                         / A[2, 2, 2, 2])
        return np.ascontiguousarray(condensed)

    # --- the local solve ---------------------------------------------------------------------
    def _solve(self, F2) -> tuple[np.ndarray, np.ndarray]:
        """(λ₃, found) shaped like the batch of F̄; ``found`` False where no root exists."""
        F2 = np.asarray(F2, dtype=float)
        batch = F2.shape[2:]
        flat = F2.reshape(2, 2, -1)
        last = self._last
        if last is not None and last[0].shape == flat.shape and np.array_equal(last[0], flat):
            return last[1].reshape(batch), last[2].reshape(batch)
        guess = last[1].copy() if last is not None and last[1].shape == flat.shape[2:] else np.ones(flat.shape[2])
        guess = np.where(np.isfinite(guess) & (guess > 0), guess, 1.0)
        lam, ok = self._newton(flat, guess)
        retry = np.flatnonzero(~ok)
        if len(retry):
            lam_r, ok_r = self._bisection(flat[:, :, retry])
            lam[retry], ok[retry] = lam_r, ok_r
        self._last = (flat.copy(), lam, ok)
        return lam.reshape(batch), ok.reshape(batch)

    def _p33(self, F2: np.ndarray, lam: np.ndarray, slope: bool = False):
        F3 = embed(F2, lam)
        with np.errstate(all="ignore"):
            p33 = self.base.stress(F3)[2, 2]
            if not slope:
                return p33
            return p33, self.base.tangent(F3)[2, 2, 2, 2]

    def _newton(self, F2: np.ndarray, lam: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Plain Newton on all points; ``ok`` marks the points that converged safely."""
        ok = np.zeros(lam.shape, dtype=bool)
        active = np.arange(lam.size)
        for _ in range(NEWTON_ITERATIONS):
            if not len(active):
                break
            p33, a3333 = self._p33(F2[:, :, active], lam[active], slope=True)
            with np.errstate(all="ignore"):
                step = -p33 / a3333
            new = lam[active] + step
            safe = np.isfinite(new) & (a3333 > 0) & (new > LAMBDA3_MIN) & (new < LAMBDA3_MAX)
            lam[active[safe]] = new[safe]
            done = safe & (np.abs(step) <= NEWTON_STEP_TOL * new)
            ok[active[done]] = True
            active = active[safe & ~done]  # unsafe points go to the bisection fallback
        return lam, ok

    def _bisection(self, F2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Bracket the root from λ₃ = 1 geometrically (down if P₃₃(1) > 0, up if < 0: P₃₃
        increases with λ₃ across the root), then bisect; ``ok`` False where no bracket exists."""
        n = F2.shape[2]
        lo, hi = np.ones(n), np.ones(n)
        g_lo = g_hi = g1 = self._p33(F2, lo)
        down, up = g1 > 0, g1 < 0
        while True:
            move_lo = down & ~(g_lo < 0) & (lo > LAMBDA3_MIN)
            move_hi = up & ~(g_hi > 0) & (hi < LAMBDA3_MAX)
            if not (move_lo.any() or move_hi.any()):
                break
            shrink = move_lo & (g_lo > 0)  # the old lower end still has P₃₃ > 0: new upper end
            hi, g_hi = np.where(shrink, lo, hi), np.where(shrink, g_lo, g_hi)
            grow = move_hi & (g_hi < 0)
            lo, g_lo = np.where(grow, hi, lo), np.where(grow, g_hi, g_lo)
            lo = np.where(move_lo, np.maximum(lo / 2, LAMBDA3_MIN), lo)
            hi = np.where(move_hi, np.minimum(hi * 2, LAMBDA3_MAX), hi)
            g_lo = np.where(move_lo, self._p33(F2, lo), g_lo)
            g_hi = np.where(move_hi, self._p33(F2, hi), g_hi)
        ok = ((g_lo < 0) & (g_hi > 0)) | (g1 == 0)
        for _ in range(BISECTION_ITERATIONS):
            if np.all(hi - lo <= 4 * np.finfo(float).eps * hi):
                break
            mid = 0.5 * (lo + hi)
            below = self._p33(F2, mid) < 0
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        return np.where(g1 == 0, 1.0, 0.5 * (lo + hi)), ok


def plane_model(base, plane: str):
    """The 2D reduction ``plane`` ("stress" or "strain") of a 3D material ``base``."""
    models = {"stress": PlaneStress, "strain": PlaneStrain}
    if plane not in models:
        raise ValueError(f"specimen.plane must be one of {', '.join(models)}, got {plane!r}")
    return models[plane](base)
