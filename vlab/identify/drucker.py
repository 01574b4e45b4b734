"""Drucker stability of a fitted card: dτ : dε > 0 for every increment of logarithmic strain.

With ε_i = ln λ_i and ψ̂(ε) = ψ(e^ε1, e^ε2, e^ε3), the principal Kirchhoff stresses are
τ_i = ∂ψ̂/∂ε_i and Drucker's condition is that the Hessian D_ij = ∂τ_i/∂ε_j is positive definite:
- incompressible: ε3 = −ε1 − ε2 and D is the 2 × 2 Hessian of ψ̂(ε1, ε2), D_ij = ∂(w_i − w_3)/∂ε_j;
- compressible:   the 3 × 3 D at the solved homogeneous state of each kind.
The derivatives are complex steps in ε (exact). Per kind the stretch is scanned from 1 up to 10
(tension) and down to 0.1 (compression) as Abaqus' material evaluation does; the first unstable
stretch is refined by bisection to 1e-6. Paths (incompressible principal stretches):
uniaxial (λ, λ^-½, λ^-½), equibiaxial (λ, λ, λ^-2), planar (λ, 1, λ^-1), simple shear (λ+, 1, λ−)
with γ = λ+ − 1/λ+ (tension only: γ and −γ are the same state).

A law defined only below a limit (Gent: Ī1 − 3 < Jm) is not unstable where its chains lock: the
scan stops there and reports ``locks_at`` (refined like an instability), so the locking stretch
is never mistaken for a loss of Drucker stability. States outside the domain have no D (NaN in
the stability map).
"""

from __future__ import annotations

import numpy as np

from vlab.identify.jacobian import H
from vlab.identify.states import Constitutive, principal_tau

__all__ = ["admissible", "min_eigenvalue", "kind_stability", "stability_map", "states_stability", "PATHS"]

LAM_MAX, LAM_MIN = 10.0, 0.1


def _c_K(model: Constitutive, x):
    c, K = model.split(np.asarray(x, float))
    return [complex(v) for v in c], (None if K is None else complex(K))


def _tau(model, c, K, eps):
    """Stresses whose ε-gradient is D: (w_i − w_3) for i = 1, 2 (incompressible) or τ_i."""
    lam = [np.exp(e) for e in eps]
    if model.bulk == "incompressible":
        lam3 = np.exp(-eps[0] - eps[1])
        w = model.law.w(c, lam[0], lam[1], lam3)
        return [w[0] - w[2], w[1] - w[2]]
    return list(principal_tau(model, c, K, *lam))


def admissible(model: Constitutive, x, eps: np.ndarray) -> np.ndarray:
    """States (columns of eps) inside the law's domain: finite log strains and, for a law with a
    margin (Gent), a positive margin at the isochoric stretches λ̄_i = exp(ε_i − Σε/3)."""
    eps = np.asarray(eps, float)
    ok = np.all(np.isfinite(eps), axis=0)
    if model.law.margin is None:
        return ok
    c, _ = model.split(np.asarray(x, float))
    full = eps if eps.shape[0] == 3 else np.vstack([eps, -eps[0] - eps[1]])
    with np.errstate(invalid="ignore"):
        lam_bar = np.exp(full - full.sum(axis=0) / 3.0)
        return ok & (model.law.margin(c, *lam_bar) > 0)


def min_eigenvalue(model: Constitutive, x, eps: np.ndarray) -> np.ndarray:
    """Smallest eigenvalue of D (MPa) at log strains eps (k, n): k = 2 (incompressible) or 3;
    NaN at states outside the law's domain (``admissible``)."""
    eps = np.asarray(eps, float)
    inside = admissible(model, x, eps)
    out = np.full(eps.shape[1], np.nan)
    if inside.any():
        out[inside] = _min_eigenvalue(model, x, eps[:, inside])
    return out


def _min_eigenvalue(model: Constitutive, x, eps: np.ndarray) -> np.ndarray:
    c, K = _c_K(model, x)
    k = eps.shape[0]
    D = np.empty((eps.shape[1], k, k))
    for j in range(k):
        e = eps.astype(complex)
        e[j] += 1j * H
        col = _tau(model, c, K, list(e))
        for i in range(k):
            D[:, i, j] = np.imag(col[i]) / H
    D = 0.5 * (D + np.transpose(D, (0, 2, 1)))
    return np.linalg.eigvalsh(D)[:, 0]


PATHS = {
    "uniaxial": lambda lam: (lam, lam ** -0.5),
    "equibiaxial": lambda lam: (lam, lam),
    "planar": lambda lam: (lam, np.ones_like(lam)),
    "biaxial": None,
}


def _state_eps(model: Constitutive, x, kind: str, lam: np.ndarray) -> np.ndarray:
    """Log strains of the kind's state at stretches lam (incompressible: 2 rows; else 3)."""
    from vlab.identify.states import _solve_free, _stretches

    l1, l2 = PATHS[kind](lam)
    if model.bulk == "incompressible":
        return np.log(np.vstack([l1, l2]))
    c, K = model.split(np.asarray(x, float))
    with np.errstate(divide="ignore", invalid="ignore"):  # past a locking stretch: NaN, judged by admissible
        t = np.real(_solve_free(model, [np.asarray(v) for v in c], K, kind, lam, None))
        return np.log(np.vstack(_stretches(kind, lam, l2, t)))


def _first_limit(model, x, kind, lo, hi) -> tuple[str, float] | None:
    """The first stretch from lo towards hi where D loses definiteness ("unstable") or the law's
    domain ends ("locks"), or None: scanned on a log grid, refined by bisection to 1e-7."""
    grid = np.geomspace(lo, hi, 400)
    good = _stable(model, x, kind, grid)
    if good.all():
        return None
    i = int(np.argmin(good))
    a, b = (grid[i - 1], grid[i]) if i > 0 else (lo, lo)
    for _ in range(60 if i > 0 else 0):
        m = np.sqrt(a * b)
        if _stable(model, x, kind, np.array([m]))[0]:
            a = m
        else:
            b = m
        if abs(np.log(b / a)) < 1e-7:  # (the scan may run downwards: b < a)
            break
    inside = admissible(model, x, _state_eps(model, x, kind, np.array([b])))[0]
    return ("unstable" if inside else "locks"), float(b)


def _stable(model, x, kind, lam) -> np.ndarray:
    """Inside the domain and D positive definite (NaN compares False)."""
    return min_eigenvalue(model, x, _state_eps(model, x, kind, lam)) > 0


def _side(model, x, kind, lo, hi) -> dict:
    limit = _first_limit(model, x, kind, lo, hi)
    what, lam = limit if limit else (None, None)
    return {"unstable_from": lam if what == "unstable" else None,
            "locks_at": lam if what == "locks" else None, "scanned_to": hi}


def kind_stability(model: Constitutive, x, kind: str, fitted: tuple[float, float] | None) -> dict:
    """Stable stretch range of a kind (tension up to, compression down to) and whether the fitted
    stretch range lies inside it. ``fitted``: (min, max) stretch of the data (or shear for
    simple shear)."""
    path = "planar" if kind == "simple-shear" else kind
    out = {"tension": _side(model, x, path, 1.0 + 1e-9, LAM_MAX),
           "compression": None if kind == "simple-shear" else _side(model, x, path, 1.0 - 1e-9, LAM_MIN)}
    up = out["tension"]["unstable_from"] or out["tension"]["locks_at"]  # the end of the usable range
    down = None if kind == "simple-shear" else (out["compression"]["unstable_from"] or out["compression"]["locks_at"])
    if kind == "simple-shear":
        for key in ("unstable_from", "locks_at"):
            lam = out["tension"][key]
            out["tension"][key + "_shear"] = None if lam is None else float(lam - 1.0 / lam)
    if fitted is not None:
        lo, hi = fitted
        if kind == "simple-shear":  # compare in γ
            g_up = out["tension"]["unstable_from_shear"] or out["tension"]["locks_at_shear"]
            out["stable_over_fitted_range"] = bool(g_up is None or max(abs(lo), abs(hi)) < g_up)
        else:
            out["stable_over_fitted_range"] = bool((up is None or hi < up) and (down is None or lo > down))
        out["fitted_range"] = [float(lo), float(hi)]
    return out


def states_stability(model: Constitutive, x, stretches) -> dict:
    """Drucker's condition at given states, principal stretches (3, n): the material points a
    closed-form data set reaches (vlab.identify.kinds, FitKind.states: a cylinder's radius, a
    sphere's wall), which lie on no single scanned path. The smallest eigenvalue of D over them
    (MPa) and whether D is positive definite at every one (a state outside the law's domain is not).
    Incompressible: ε = (ln λ1, ln λ2) (the states have λ1 λ2 λ3 = 1); else the three ln λ_i."""
    lam = np.asarray(stretches, float)
    eps = np.log(lam[:2] if model.bulk == "incompressible" else lam)
    m = min_eigenvalue(model, x, eps)
    return {"states": int(lam.shape[1]), "min_eigenvalue": float(np.nanmin(m)) if np.isfinite(m).any() else None,
            "stable": bool(np.all(m > 0))}


def stability_map(model: Constitutive, x, n: int = 121) -> dict:
    """min eig D over the (λ1, λ2) plane on a log grid 0.1..10 (incompressible λ3 = 1/(λ1 λ2);
    compressible: the 3 × 3 D of the isochoric state λ3 = 1/(λ1 λ2))."""
    lam = np.geomspace(LAM_MIN, LAM_MAX, n)
    L1, L2 = np.meshgrid(lam, lam, indexing="ij")
    e1, e2 = np.log(L1).ravel(), np.log(L2).ravel()
    eps = np.vstack([e1, e2]) if model.bulk == "incompressible" else np.vstack([e1, e2, -e1 - e2])
    m = min_eigenvalue(model, x, eps).reshape(n, n)
    return {"stretch": lam, "min_eigenvalue": m}
