"""Sub-pixel refinement: inverse-compositional Gauss–Newton (IC-GN) with an affine shape function
on the zero-normalised sum of squared differences, vectorised over subsets.

For a subset of the reference image f centred at (x₀, y₀) with local coordinates ξ = (Δx, Δy),
the affine warp with p = (u, u_x, u_y, v, v_x, v_y) (px, –, –, px, –, –) is

    W(ξ; p) = [[1 + u_x, u_y, u], [v_x, 1 + v_y, v], [0, 0, 1]] · (Δx, Δy, 1)ᵀ

and the criterion  C(p) = Σ_ξ [ (f(ξ) − f̄)/Δf − (g(W(ξ; p)) − ḡ)/Δg ]²  (ZNSSD; Δf, Δg the
root sums of squares about the means f̄, ḡ). IC-GN linearises the *reference* side, so the
steepest-descent images J = ∇f · ∂W/∂p = (f_x, f_x Δx, f_x Δy, f_y, f_y Δx, f_y Δy) and the
Hessian H = Σ Jᵀ J are computed once per subset:

    Δp = −H⁻¹ Σ Jᵀ [ (f − f̄) − (Δf/Δg)(g(W(ξ; p)) − ḡ) ],   W(p) ← W(p) ∘ W(Δp)⁻¹

until ‖Δp‖ (with the gradient terms scaled by the subset half-width, so every term is in px) is
below the tolerance. The deformed image g is interpolated with bicubic B-splines (its spline
coefficients computed once per image, scipy.ndimage); f's gradient is the fourth-order central
difference (f(x−2) − 8 f(x−1) + 8 f(x+1) − f(x+2)) / 12. The ZNCC reported is 1 − C/2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

# per-subset outcome codes (the CSV writes their names)
# (OUTSIDE: a subset the caller's region of interest leaves out, never correlated)
OK, NO_TEXTURE, LEFT_IMAGE, NOT_CONVERGED, LOW_CORRELATION, OUTSIDE = range(6)
STATUS = {OK: "ok", NO_TEXTURE: "no texture", LEFT_IMAGE: "left the image",
          NOT_CONVERGED: "did not converge", LOW_CORRELATION: "low correlation",
          OUTSIDE: "outside the region of interest"}
ORDERS = {"bicubic": 3, "biquintic": 5}


def gradients(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(∂f/∂x, ∂f/∂y) by the fourth-order central difference (edge rows and columns mirrored)."""
    k = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / 12.0
    fx = ndimage.correlate1d(image, k, axis=1, mode="mirror")
    fy = ndimage.correlate1d(image, k, axis=0, mode="mirror")
    return fx, fy


@dataclass
class Reference:
    """Everything IC-GN needs from the reference subsets, computed once per reference image."""

    image: np.ndarray  # f (rows, columns)
    fx: np.ndarray  # ∂f/∂x, ∂f/∂y (rows, columns)
    fy: np.ndarray
    cx: np.ndarray  # integer subset centres (px), shape (n,)
    cy: np.ndarray
    half: int
    fmean: np.ndarray  # f̄ per subset, shape (n,)
    df: np.ndarray  # Δf, shape (n,)
    Hinv: np.ndarray  # (n, 6, 6)
    textured: np.ndarray  # bool (n,): Δf > 0 and H well conditioned

    def offsets(self) -> tuple[np.ndarray, np.ndarray]:
        """The local coordinates (Δx, Δy) of a subset's pixels, row by row."""
        o = np.arange(-self.half, self.half + 1)
        DY, DX = np.meshgrid(o, o, indexing="ij")
        return DX.ravel(), DY.ravel()

    def gather(self, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(f − f̄, J) of the subsets ``idx``: (k, P) and the steepest-descent images (k, P, 6)."""
        dx, dy = self.offsets()
        rows, cols = self.cy[idx, None] + dy, self.cx[idx, None] + dx
        f0 = self.image[rows, cols] - self.fmean[idx, None]
        gx, gy = self.fx[rows, cols], self.fy[rows, cols]
        return f0, np.stack([gx, gx * dx, gx * dy, gy, gy * dx, gy * dy], axis=2)


CHUNK = 1024  # subsets per numpy batch: bounds J to CHUNK · P · 6 values


def prepare(ref: np.ndarray, cx: np.ndarray, cy: np.ndarray, half: int, compiled: bool | None = None) -> Reference:
    """The reference side of IC-GN for subsets of half-width ``half`` centred at integer (cx, cy)
    (f̄, Δf, H⁻¹). A subset without texture (uniform grey, or a gradient in one direction only, so
    H is singular) is marked so and never iterated."""
    from vlab.dic import kernel

    fx, fy = gradients(ref)
    n = cx.size
    cx, cy = np.ascontiguousarray(cx, dtype=np.int64), np.ascontiguousarray(cy, dtype=np.int64)
    refd = Reference(ref, fx, fy, cx, cy, half, np.zeros(n), np.zeros(n), np.zeros((n, 6, 6)),
                     np.zeros(n, bool))
    H = np.zeros((n, 6, 6))
    kernels = kernel.compiled_kernels() if compiled is not False else None
    if compiled and kernels is None:
        raise RuntimeError("the compiled IC-GN needs numba (VLAB_KERNEL=numpy or numba missing)")
    if kernels is not None:
        from vlab import jit
        jit.call(kernels.prepare_batch, ref, fx, fy, cx, cy, half, refd.fmean, refd.df, H)
    else:
        _prepare_numpy(refd, H)
    # scale-free conditioning test: H in units where the gradient terms carry the half-width
    scale = np.array([1.0, half, half, 1.0, half, half])
    lam = np.linalg.eigvalsh(H / np.outer(scale, scale))
    level = max(float(np.abs(ref).max()), 1e-300)
    conditioned = (lam[:, -1] > 0) & (lam[:, 0] > 1e-10 * lam[:, -1])
    refd.textured = (refd.df > 1e-9 * level * (2 * half + 1)) & conditioned
    refd.Hinv[refd.textured] = np.linalg.inv(H[refd.textured])
    return refd


def _prepare_numpy(refd: Reference, H: np.ndarray) -> None:
    """The numpy twin of the kernel's prepare_batch: f̄, Δf (in refd) and H, in place."""
    dx, dy = refd.offsets()
    for a in range(0, refd.cx.size, CHUNK):
        idx = np.arange(a, min(refd.cx.size, a + CHUNK))
        refd.fmean[idx] = refd.image[refd.cy[idx, None] + dy, refd.cx[idx, None] + dx].mean(axis=1)
        f0, J = refd.gather(idx)
        refd.df[idx] = np.sqrt((f0 * f0).sum(axis=1))
        H[idx] = np.matmul(J.transpose(0, 2, 1), J)


def _warp(p: np.ndarray) -> np.ndarray:
    """The 3 × 3 affine matrices of parameters p (n, 6)."""
    W = np.zeros((p.shape[0], 3, 3))
    W[:, 0] = np.stack([1 + p[:, 1], p[:, 2], p[:, 0]], axis=1)
    W[:, 1] = np.stack([p[:, 4], 1 + p[:, 5], p[:, 3]], axis=1)
    W[:, 2, 2] = 1.0
    return W


def _params(W: np.ndarray) -> np.ndarray:
    return np.stack([W[:, 0, 2], W[:, 0, 0] - 1, W[:, 0, 1], W[:, 1, 2], W[:, 1, 0], W[:, 1, 1] - 1], axis=1)


def coefficients(image: np.ndarray, interpolation: str = "bicubic") -> np.ndarray:
    """The B-spline coefficients of a deformed image (computed once, used at every iteration)."""
    return ndimage.spline_filter(image, order=ORDERS[interpolation], mode="mirror")


def refine(refd: Reference, coeffs: np.ndarray, p0: np.ndarray, idx: np.ndarray, interpolation: str = "bicubic",
           tolerance: float = 1e-4, max_iterations: int = 50,
           compiled: bool | None = None) -> tuple[np.ndarray, ...]:
    """IC-GN of the subsets ``idx`` from the starting parameters p0 (len(idx), 6):
    (p, zncc, iterations, status) for those subsets. The compiled kernel (vlab.dic.kernel) does
    the same for bicubic interpolation when numba is available (``compiled``: None picks it,
    False the numpy twin, True requires it)."""
    from vlab.dic import kernel

    kernels = kernel.compiled_kernels() if compiled is not False and interpolation == "bicubic" else None
    if compiled and kernels is None:
        raise RuntimeError("the compiled IC-GN needs numba and bicubic interpolation")
    n = idx.size
    p = np.ascontiguousarray(p0, dtype=float).copy()
    zncc = np.full(n, np.nan)
    iterations = np.zeros(n, dtype=np.int64)
    status = np.where(refd.textured[idx], NOT_CONVERGED, NO_TEXTURE).astype(np.int64)
    if kernels is not None:
        from vlab import jit
        jit.call(kernels.refine_batch, refd.image, refd.fx, refd.fy, coeffs, refd.cx, refd.cy, refd.half,
                 refd.fmean, refd.df, refd.Hinv, np.ascontiguousarray(idx, dtype=np.int64), p, tolerance,
                 max_iterations, zncc, iterations, status)
        return p, zncc, iterations, status
    for a in range(0, n, CHUNK):
        sl = slice(a, min(n, a + CHUNK))
        _refine_numpy(refd, coeffs, idx[sl], p[sl], zncc[sl], iterations[sl], status[sl], ORDERS[interpolation],
                      tolerance, max_iterations)
    return p, zncc, iterations, status


def _refine_numpy(refd, coeffs, idx, p, zncc, iterations, status, order, tolerance, max_iterations):
    """The numpy twin of the kernel, on one chunk of subsets (arrays updated in place)."""
    h, w = coeffs.shape
    dx, dy = refd.offsets()
    f0_all, J_all = refd.gather(idx)
    scale = np.array([1.0, refd.half, refd.half, 1.0, refd.half, refd.half])
    active = np.flatnonzero(status == NOT_CONVERGED)
    for it in range(1, max_iterations + 1):
        if active.size == 0:
            break
        pa = p[active]
        x = refd.cx[idx[active], None] + (1 + pa[:, 1:2]) * dx + pa[:, 2:3] * dy + pa[:, 0:1]
        y = refd.cy[idx[active], None] + pa[:, 4:5] * dx + (1 + pa[:, 5:6]) * dy + pa[:, 3:4]
        inside = (x.min(1) >= 0) & (x.max(1) <= w - 1) & (y.min(1) >= 0) & (y.max(1) <= h - 1)
        status[active[~inside]] = LEFT_IMAGE
        active, x, y = active[inside], x[inside], y[inside]
        if active.size == 0:
            break
        g = ndimage.map_coordinates(coeffs, [y.ravel(), x.ravel()], order=order, prefilter=False,
                                    mode="mirror").reshape(x.shape)
        g0 = g - g.mean(axis=1, keepdims=True)
        dg = np.sqrt((g0 * g0).sum(axis=1))
        flat = dg <= 0
        status[active[flat]] = NO_TEXTURE
        active, g0, dg = active[~flat], g0[~flat], dg[~flat]
        f0, df = f0_all[active], refd.df[idx[active]]
        e = f0 - (df / dg)[:, None] * g0
        zncc[active] = 1.0 - 0.5 * ((e / df[:, None]) ** 2).sum(axis=1)
        b = np.einsum("npi,np->ni", J_all[active], e)
        dp = -np.einsum("nij,nj->ni", refd.Hinv[idx[active]], b)
        p[active] = _params(_warp(p[active]) @ np.linalg.inv(_warp(dp)))
        iterations[active] = it
        done = np.sqrt(((dp * scale) ** 2).sum(axis=1)) < tolerance
        status[active[done]] = OK
        active = active[~done]
