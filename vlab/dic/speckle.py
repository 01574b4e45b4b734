"""An analytic speckle pattern and its exact rendering through a known displacement.

The pattern is a sum of Gaussian speckles on a bright background, in the reference
configuration X (pixels):

    I(X) = d + (b − d) exp(−κ Σ_k exp(−|X − X_k|² / r²)),   r = size / 2,  κ = 1.5

(grey levels: b the bright background, d the dark limit that overlapping speckles approach; the
outer exponential is an absorption law, so overlaps stay within [d, b] and I is smooth)

with speckle centres X_k drawn uniformly (``density`` = share of the area covered by discs of
diameter ``size``, so N = density · area / (π r²)). A deformed image is rendered by evaluating I at
the reference point X = φ⁻¹(x) of every sub-sample x of a pixel and averaging the s × s
sub-samples (the pixel integrates the light falling on it), so the image of a known field is
exact up to the supersampling quadrature: no image interpolation is involved.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

KAPPA = 1.5  # absorption per unit speckle coverage
CUTOFF = 3.5  # speckles count within 3.5 r only: exp(−12.25) ≈ 5e-6 of their depth is dropped


@dataclass(frozen=True)
class Pattern:
    """Speckle centres (x, y) in px, radius r in px, background b and dark limit d in grey levels."""

    centres: np.ndarray
    radius: float
    background: float
    dark: float


def make_pattern(shape: tuple[int, int], size: float = 4.0, density: float = 0.5, seed: int = 0,
                 levels: float = 65535.0, margin: float = 20.0) -> Pattern:
    """A pattern covering an image of ``shape`` (rows, columns) plus ``margin`` px on each side
    (material that moves into view). Background 0.9, dark limit 0.05 of ``levels``."""
    rows, cols = shape
    r = size / 2.0
    lo, hi = np.array([-margin, -margin]), np.array([cols + margin, rows + margin])
    n = int(round(density * np.prod(hi - lo) / (np.pi * r * r)))
    centres = lo + np.random.default_rng(seed).random((n, 2)) * (hi - lo)
    return Pattern(centres, r, 0.9 * levels, 0.05 * levels)


@dataclass(frozen=True)
class CellTable:
    """The speckles binned in square cells of side CUTOFF · r: cell (kx, ky) is row ky · ncx + kx
    of ``table`` (ncx · ncy, slots, 2), its centres first, then +inf; a border of empty cells
    around the pattern."""

    origin: np.ndarray
    cell: float
    ncx: int
    ncy: int
    table: np.ndarray


def cell_table(pattern: Pattern) -> CellTable:
    cell = CUTOFF * pattern.radius
    c = pattern.centres
    origin = c.min(axis=0) - cell
    ij = np.floor((c - origin) / cell).astype(np.int64)
    ncx, ncy = ij.max(axis=0) + 3
    key = ij[:, 1] * ncx + ij[:, 0]
    order = np.argsort(key, kind="stable")
    key_sorted = key[order]
    counts = np.bincount(key_sorted, minlength=ncx * ncy)
    slots = int(counts.max()) if counts.size else 0
    start = np.concatenate(([0], np.cumsum(counts)[:-1]))
    rank = np.arange(len(key_sorted)) - start[key_sorted]
    table = np.full((ncx * ncy, max(slots, 1), 2), np.inf)
    table[key_sorted, rank] = c[order]
    return CellTable(origin, float(cell), int(ncx), int(ncy), table)


def intensity(pattern: Pattern, X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """I(X, Y) at arbitrary reference points (any shape), the sum over the speckles within
    CUTOFF · r of each point (so I does not depend on the units or origin of X), found in the
    cell table: the 3 × 3 cells around the point. (vlab.dic.camera_kernel compiles the same sum.)"""
    t = cell_table(pattern)
    origin, cell, ncx, ncy = t.origin, t.cell, t.ncx, t.ncy
    x, y = X.ravel(), Y.ravel()
    cx = np.floor((x - origin[0]) / cell).astype(np.int64)
    cy = np.floor((y - origin[1]) / cell).astype(np.int64)
    inv_r2 = 1.0 / pattern.radius ** 2
    total = np.zeros(x.size)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            kx, ky = np.clip(cx + dx, 0, ncx - 1), np.clip(cy + dy, 0, ncy - 1)
            cells = t.table[ky * ncx + kx]  # (n, slots, 2)
            d2 = (cells[..., 0] - x[:, None]) ** 2 + (cells[..., 1] - y[:, None]) ** 2
            q = d2 * inv_r2
            total += np.where(q <= CUTOFF ** 2, np.exp(-q), 0.0).sum(axis=1)
    b, d = pattern.background, pattern.dark
    return (d + (b - d) * np.exp(-KAPPA * total)).reshape(X.shape)


def render(pattern: Pattern, shape: tuple[int, int], inverse: Callable | None = None,
           supersample: int = 4, chunk_rows: int = 64) -> np.ndarray:
    """The image (rows, columns) of the pattern seen through the deformation whose inverse map
    ``inverse(x, y) -> (X, Y)`` is given (None: the reference image), each pixel the mean of
    ``supersample``² sub-samples at the centres of its sub-cells."""
    rows, cols = shape
    s = supersample
    sub = (np.arange(s) + 0.5) / s - 0.5
    out = np.empty(shape)
    for r0 in range(0, rows, chunk_rows):
        r1 = min(rows, r0 + chunk_rows)
        yy = (np.arange(r0, r1)[:, None] + sub[None, :]).ravel()
        xx = (np.arange(cols)[:, None] + sub[None, :]).ravel()
        x, y = np.meshgrid(xx, yy)
        X, Y = (x, y) if inverse is None else inverse(x, y)
        values = intensity(pattern, np.asarray(X, float), np.asarray(Y, float))
        out[r0:r1] = values.reshape(r1 - r0, s, cols, s).mean(axis=(1, 3))
    return out


def translation(u: float, v: float) -> Callable:
    """The inverse map of a rigid translation x = X + (u, v)."""
    return lambda x, y: (x - u, y - v)


def homogeneous(exx: float, eyy: float, centre: tuple[float, float] = (0.0, 0.0)) -> Callable:
    """The inverse map of a homogeneous stretch about ``centre``: x − c = (1 + εxx)(X − c) in x,
    likewise in y, so ∂u/∂X = εxx, ∂v/∂Y = εyy (Green–Lagrange Exx = εxx + εxx²/2)."""
    cx, cy = centre
    return lambda x, y: (cx + (x - cx) / (1 + exx), cy + (y - cy) / (1 + eyy))


def sinusoid(amplitude: float, period: float, iterations: int = 30) -> Callable:
    """The inverse map of u(X, Y) = 0, v(X, Y) = A sin(2π X / period): x = X, y = Y + v(X), so the
    inverse is exact (X = x, Y = y − A sin(2π x / period))."""
    k = 2 * np.pi / period
    return lambda x, y: (x, y - amplitude * np.sin(k * x))


def add_noise(image: np.ndarray, sigma: float, seed: int = 1, levels: float = 65535.0) -> np.ndarray:
    """The image plus Gaussian grey-level noise of standard deviation ``sigma`` · levels, clipped to
    the sensor's range [0, levels]."""
    noisy = image + np.random.default_rng(seed).normal(0.0, sigma * levels, image.shape)
    return np.clip(noisy, 0.0, levels)
