"""Ogden's compiled point kernels: the principal frame, ψ_iso, τ, c, g and P_iso in one pass,
and the nine isotropic tangent forms (vlab.materials.ogden states the formulas; the numpy path
there is the twin and the reference of tests/test_principal_eig.py).

Per quadrature point ``ogden_state`` does what Ogden's numpy path does with a batched eigh, a
dozen einsums and N passes over (3,3,*batch) temporaries:

    C = FᵀF = Σ λ_A² N_A ⊗ N_A  (vlab.materials.principal_eig.eig3),  n_A = F N_A / λ_A
    ē_A = ln λ_A − ⅓ Σ ln λ_B,  per term p: ψ_iso += 2μₚ Σ_A ē_A² φ₂(αₚ ē_A)  (= 2μₚ/αₚ² Σ_A expm1(αₚ ē_A)),
    τ_A += 2μₚ (q_A − ⅓ Σ q_B), q_A = ē_A φ₁(αₚ ē_A)  (= 2μₚ/αₚ (λ̄_A^αₚ − s_p/3); φ: vlab.materials.ogden),  c_AB += 2μₚ (λ̄_A^αₚ (δ_AB − ⅓) − ⅓ λ̄_B^αₚ + s_p/9),
    g_AB += 2μₚ/αₚ λ̄_B^αₚ expm1(αₚ d)/d  (d = ε_A − ε_B; αₚ(1 + αₚ d/2) for |αₚ d| < 1e−8;
              symmetric; for |αₚ d| ≥ 1/8 as (λ̄_A^αₚ − λ̄_B^αₚ)/d, no transcendental),
    P_iso = Σ_A τ_A/λ_A n_A ⊗ N_A                                                     (MPa)

``ogden_forms`` writes the tangent A = Σ w_AB M_AA ⊗ M_BB + Σ_{A≠B} [t1_AB M_AB ⊗ M_AB +
t2_AB M_AB ⊗ M_BA] (M_AB = n_A ⊗ N_B; w, t1 = (a + b)/2, t2 = (a − b)/2 of vlab.materials.
principal) as six forms α X_iJ X_kL + β X_iL X_kJ of the compiled kernel, with no per-point
eigendecomposition: for each pair A < B, X = M_AB ± M_BA. The cross product of the symmetric
one couples M_AA with M_BB (X dFᵀ X = (M_AB : dF) M_AB + (M_BB : dF) M_AA + ... for X = M_AB + M_BA),
so in the basis M its forms give

    (AB,AB) = (BA,BA) = α₊ + β₊ + α₋,   (AB,BA) = α₊ − α₋,   (AA,BB) = (BB,AA) = β₊,

and the first form also carries B = ½ Σ_A w_AA n_A ⊗ n_A, S = ½ Σ_A w_AA N_A ⊗ N_A (the terms
B_ik δ_JL + δ_ik S_JL add ½(w_CC + w_DD) to every diagonal entry (CD,CD), w_AA to (AA,AA)).
Matching the targets: β₊ = w_AB, β₋ = 0, α± = ½ (t1 ± t2 − w_AB − h_AB), h_AB = ½ (w_AA + w_BB).
Six forms instead of nine: the assembly pass runs once per form.

Both kernels run over point ranges; batches of ≥ 4096 points are split into jit.threads()
chunks run side by side (numba prange; each point is written by one thread only).
"""

from __future__ import annotations

import numpy as np

from vlab.materials.principal_eig import SOURCE as _EIG_SOURCE

__all__ = ["kernels"]

_SOURCE = _EIG_SOURCE + '''

@numba.njit(inline="always", **_OPTIONS)
def _pair(mu2, al, La, Lb, d):
    """2μ/α λ̄_B^α expm1(α d)/d = 2μ λ̄_B^α φ₁(α d) (limit 1 + α d/2 at |α d| < 1e−8), and for
    |α d| ≥ 1/8 the same as (λ̄_A^α − λ̄_B^α)/d (relative error < 2e−15, no transcendental)."""
    x = al * d
    if abs(x) < 0.125:
        return mu2 * Lb * _phi1(x)
    return mu2 / al * (La - Lb) / d


@numba.njit(inline="always", **_OPTIONS)
def _phi1(x):
    """expm1(x)/x, 1 + x/2 for |x| < 1e−8 (vlab.materials.ogden._phi1)."""
    if abs(x) < 1e-8:
        return 1.0 + 0.5 * x
    return math.expm1(x) / x


@numba.njit(inline="always", **_OPTIONS)
def _phi2(x):
    """(eˣ − 1 − x)/x²: Σ xᵏ/(k+2)! to k = 14 for |x| < ½, else (expm1(x) − x)/x² (ogden._phi2)."""
    if abs(x) < 0.5:
        term, total = 0.5, 0.5
        for k in range(1, 15):
            term *= x / (k + 2)
            total += term
        return total
    return (math.expm1(x) - x) / (x * x)


@numba.njit(**_OPTIONS)
def ogden_state(F, mus, alphas, lam, N, n, eps, psi, tau, c, g, P, start, stop):
    """(module docstring) F (3,3,p) admissible, points start:stop; outputs as PrincipalFrame
    and principal_iso."""
    for p in range(start, stop):
        frame_point(F, p, lam, N, n)
        for A in range(3):
            eps[A, p] = math.log(lam[A, p])
        e0, e1, e2 = eps[0, p], eps[1, p], eps[2, p]
        mean = (e0 + e1 + e2) / 3.0
        # accumulate in scalars, store once: the outputs are strided (p is their last axis)
        ps = t0 = t1 = t2 = 0.0
        c00 = c11 = c22 = c01 = c02 = c12 = 0.0
        g00 = g11 = g22 = g01 = g02 = g12 = 0.0
        for k in range(mus.shape[0]):
            mu2, al = 2.0 * mus[k], alphas[k]
            b0, b1, b2 = e0 - mean, e1 - mean, e2 - mean   # ē_A
            m0, m1, m2 = math.expm1(al * b0), math.expm1(al * b1), math.expm1(al * b2)
            L0, L1, L2 = 1.0 + m0, 1.0 + m1, 1.0 + m2   # λ̄_A^α (exp = 1 + expm1 within an ulp)
            s = L0 + L1 + L2
            # ψ, τ through φ₂, φ₁ (no 1/α beside λ̄^α − 1: exact for a small |α|, vlab.materials.ogden)
            ps += mu2 * (b0 * b0 * _phi2(al * b0) + b1 * b1 * _phi2(al * b1) + b2 * b2 * _phi2(al * b2))
            q0, q1, q2 = b0 * _phi1(al * b0), b1 * _phi1(al * b1), b2 * _phi1(al * b2)
            qm = (q0 + q1 + q2) / 3.0
            t0 += mu2 * (q0 - qm)
            t1 += mu2 * (q1 - qm)
            t2 += mu2 * (q2 - qm)
            c00 += mu2 * (L0 / 3.0 + s / 9.0)
            c11 += mu2 * (L1 / 3.0 + s / 9.0)
            c22 += mu2 * (L2 / 3.0 + s / 9.0)
            c01 += mu2 * (s / 9.0 - (L0 + L1) / 3.0)
            c02 += mu2 * (s / 9.0 - (L0 + L2) / 3.0)
            c12 += mu2 * (s / 9.0 - (L1 + L2) / 3.0)
            g00 += mu2 * L0
            g11 += mu2 * L1
            g22 += mu2 * L2
            g01 += _pair(mu2, al, L0, L1, e0 - e1)
            g02 += _pair(mu2, al, L0, L2, e0 - e2)
            g12 += _pair(mu2, al, L1, L2, e1 - e2)
        psi[p] = ps
        tau[0, p], tau[1, p], tau[2, p] = t0, t1, t2
        c[0, 0, p], c[1, 1, p], c[2, 2, p] = c00, c11, c22
        c[0, 1, p] = c[1, 0, p] = c01
        c[0, 2, p] = c[2, 0, p] = c02
        c[1, 2, p] = c[2, 1, p] = c12
        g[0, 0, p], g[1, 1, p], g[2, 2, p] = g00, g11, g22
        g[0, 1, p] = g[1, 0, p] = g01
        g[0, 2, p] = g[2, 0, p] = g02
        g[1, 2, p] = g[2, 1, p] = g12
        ts = (t0, t1, t2)
        for i in range(3):
            for J in range(3):
                v = 0.0
                for A in range(3):
                    v += ts[A] / lam[A, p] * n[i, A, p] * N[J, A, p]
                P[i, J, p] = v


@numba.njit(**_OPTIONS)
def ogden_forms(n, N, w, t1, t2, X, alpha, beta, S, Bm, start, stop):
    """(module docstring) the six forms: X (6,3,3,p), alpha, beta (6,p); S, B (3,3,p) of the
    first; points start:stop."""
    for p in range(start, stop):
        for i in range(3):
            for J in range(3):
                vb, vs = 0.0, 0.0
                for A in range(3):
                    vb += 0.5 * w[A, A, p] * n[i, A, p] * n[J, A, p]
                    vs += 0.5 * w[A, A, p] * N[i, A, p] * N[J, A, p]
                Bm[i, J, p], S[i, J, p] = vb, vs
        k = 0
        for A in range(3):
            for B in range(A + 1, 3):
                h = 0.5 * (w[A, A, p] + w[B, B, p])
                alpha[k, p] = 0.5 * (t1[A, B, p] + t2[A, B, p] - w[A, B, p] - h)
                beta[k, p] = w[A, B, p]
                alpha[k + 1, p] = 0.5 * (t1[A, B, p] - t2[A, B, p] - w[A, B, p] - h)
                beta[k + 1, p] = 0.0
                for i in range(3):
                    for J in range(3):
                        ab = n[i, A, p] * N[J, B, p]
                        ba = n[i, B, p] * N[J, A, p]
                        X[k, i, J, p] = ab + ba
                        X[k + 1, i, J, p] = ab - ba
                k += 2


@numba.njit(parallel=True, **_OPTIONS)
def ogden_state_parallel(F, mus, alphas, lam, N, n, eps, psi, tau, c, g, P, bounds):
    for t in numba.prange(bounds.shape[0] - 1):
        ogden_state(F, mus, alphas, lam, N, n, eps, psi, tau, c, g, P, bounds[t], bounds[t + 1])


@numba.njit(parallel=True, **_OPTIONS)
def ogden_forms_parallel(n, N, w, t1, t2, X, alpha, beta, S, Bm, bounds):
    for t in numba.prange(bounds.shape[0] - 1):
        ogden_forms(n, N, w, t1, t2, X, alpha, beta, S, Bm, bounds[t], bounds[t + 1])
'''

_KERNELS: list = []
_COMPILED_FROM = 64  # points: below, the numpy path (numba's call overhead outweighs it)
_THREADED_FROM = 4096  # points: below, one thread (starting the others costs more)


def _launch(module, name: str, size: int, *args) -> None:
    """Run kernel ``name`` over points 0:size, in jit.threads() chunks from the main thread
    (numba's workqueue layer must not be entered from two threads at once: vlab.fe.compiled),
    serially otherwise."""
    import threading

    from vlab import jit, settings
    threads = jit.threads(settings.current())  # materials are called without settings in hand
    if threads > 1 and size >= _THREADED_FROM and threading.current_thread() is threading.main_thread():
        bounds = np.linspace(0, size, threads + 1).astype(np.int64)
        jit.call(getattr(module, name + "_parallel"), *args, bounds)
    else:
        jit.call(getattr(module, name), *args, 0, size)


def kernels(size: int):
    """The compiled module (``ogden_state``, ``ogden_forms``) for a batch of ``size`` points, or
    None (numba missing, VLAB_KERNEL=numpy, or a batch too small to gain)."""
    from vlab import jit, settings  # numba starts on the first large batch, not with this module
    if size < _COMPILED_FROM or not jit.available(settings.current()):
        return None
    if not _KERNELS:
        _KERNELS.append(jit.load("ogden", _SOURCE))
    return _KERNELS[0]


def state(module, F: np.ndarray, mus: np.ndarray, alphas: np.ndarray) -> dict:
    """ogden_state on F (3,3,*batch) (admissible): lam, eps, n, N, psi, tau, c, g, P reshaped."""
    batch = F.shape[2:]
    flat = np.ascontiguousarray(F, dtype=float).reshape(3, 3, -1)
    size = flat.shape[2]
    out = {"lam": np.empty((3, size)), "N": np.empty((3, 3, size)), "n": np.empty((3, 3, size)),
           "eps": np.empty((3, size)), "psi": np.empty(size), "tau": np.empty((3, size)),
           "c": np.empty((3, 3, size)), "g": np.empty((3, 3, size)), "P": np.empty((3, 3, size))}
    _launch(module, "ogden_state", size, flat, mus, alphas, out["lam"], out["N"], out["n"], out["eps"],
            out["psi"], out["tau"], out["c"], out["g"], out["P"])
    return {k: v.reshape(v.shape[:-1] + batch) for k, v in out.items()}


def forms(module, n, N, w, t1, t2) -> tuple[np.ndarray, ...]:
    """ogden_forms: (X (6,3,3,*b), alpha (6,*b), beta (6,*b), S (3,3,*b), B (3,3,*b))."""
    batch = n.shape[2:]
    flat = [np.ascontiguousarray(x, dtype=float).reshape(x.shape[:2] + (-1,)) for x in (n, N, w, t1, t2)]
    size = flat[0].shape[2]
    X, alpha, beta = np.empty((6, 3, 3, size)), np.empty((6, size)), np.empty((6, size))
    S, B = np.empty((3, 3, size)), np.empty((3, 3, size))
    _launch(module, "ogden_forms", size, *flat, X, alpha, beta, S, B)
    return (X.reshape((6, 3, 3) + batch), alpha.reshape((6,) + batch), beta.reshape((6,) + batch),
            S.reshape((3, 3) + batch), B.reshape((3, 3) + batch))
