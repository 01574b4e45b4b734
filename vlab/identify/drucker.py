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
"""

from __future__ import annotations

import numpy as np

from vlab.identify.jacobian import H
from vlab.identify.states import Constitutive, principal_tau

__all__ = ["min_eigenvalue", "kind_stability", "stability_map", "PATHS"]

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


def min_eigenvalue(model: Constitutive, x, eps: np.ndarray) -> np.ndarray:
    """Smallest eigenvalue of D (MPa) at log strains eps (k, n): k = 2 (incompressible) or 3."""
    c, K = _c_K(model, x)
    eps = np.asarray(eps, float)
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
    t = np.real(_solve_free(model, [np.asarray(v) for v in c], K, kind, lam, None))
    return np.log(np.vstack(_stretches(kind, lam, l2, t)))


def _first_unstable(model, x, kind, lo, hi) -> float | None:
    """The first stretch from lo towards hi where D loses definiteness, or None."""
    grid = np.geomspace(lo, hi, 400)
    ok = min_eigenvalue(model, x, _state_eps(model, x, kind, grid)) > 0
    if ok.all():
        return None
    i = int(np.argmin(ok))
    if i == 0:
        return float(lo)
    a, b = grid[i - 1], grid[i]
    for _ in range(60):
        m = np.sqrt(a * b)
        if min_eigenvalue(model, x, _state_eps(model, x, kind, np.array([m])))[0] > 0:
            a = m
        else:
            b = m
        if abs(np.log(b / a)) < 1e-7:  # (the scan may run downwards: b < a)
            break
    return float(b)


def kind_stability(model: Constitutive, x, kind: str, fitted: tuple[float, float] | None) -> dict:
    """Stable stretch range of a kind (tension up to, compression down to) and whether the fitted
    stretch range lies inside it. ``fitted``: (min, max) stretch of the data (or shear for
    simple shear)."""
    path = "planar" if kind == "simple-shear" else kind
    up = _first_unstable(model, x, path, 1.0 + 1e-9, LAM_MAX)
    down = None if kind == "simple-shear" else _first_unstable(model, x, path, 1.0 - 1e-9, LAM_MIN)
    out = {"tension": {"unstable_from": up, "scanned_to": LAM_MAX},
           "compression": None if kind == "simple-shear" else {"unstable_from": down, "scanned_to": LAM_MIN}}
    if kind == "simple-shear":
        out["tension"]["unstable_from_shear"] = None if up is None else float(up - 1.0 / up)
    if fitted is not None:
        lo, hi = fitted
        if kind == "simple-shear":  # compare in γ
            g_up = out["tension"]["unstable_from_shear"]
            out["stable_over_fitted_range"] = bool(g_up is None or max(abs(lo), abs(hi)) < g_up)
        else:
            out["stable_over_fitted_range"] = bool((up is None or hi < up) and (down is None or lo > down))
        out["fitted_range"] = [float(lo), float(hi)]
    return out


def stability_map(model: Constitutive, x, n: int = 121) -> dict:
    """min eig D over the (λ1, λ2) plane on a log grid 0.1..10 (incompressible λ3 = 1/(λ1 λ2);
    compressible: the 3 × 3 D of the isochoric state λ3 = 1/(λ1 λ2))."""
    lam = np.geomspace(LAM_MIN, LAM_MAX, n)
    L1, L2 = np.meshgrid(lam, lam, indexing="ij")
    e1, e2 = np.log(L1).ravel(), np.log(L2).ravel()
    eps = np.vstack([e1, e2]) if model.bulk == "incompressible" else np.vstack([e1, e2, -e1 - e2])
    m = min_eigenvalue(model, x, eps).reshape(n, n)
    return {"stretch": lam, "min_eigenvalue": m}
