"""The integer displacement of each subset: zero-normalised cross-correlation (ZNCC) over a search
window, computed for a batch of subsets at once with FFTs.

For a subset template T (s × s, zero mean) and a search window S ((s + 2R)², centred on the
subset's centre plus its guess), the ZNCC at offset (k, l) is

    C(k, l) = Σ T_ij S_{i+k, j+l} / (‖T‖ · sqrt(Σ S² − (Σ S)² / s²))

(the window sums over the s × s patch at (k, l), from cumulative sums), and the seed is the
integer offset of the largest C, its value the seed's confidence.
"""

from __future__ import annotations

import numpy as np
from scipy import fft as sfft

CHUNK = 256  # subsets per batch: bounds the memory to CHUNK · (s + 2R)² values


def _patches(image: np.ndarray, rows: np.ndarray, cols: np.ndarray, size: int) -> np.ndarray:
    """The size × size patches whose top-left pixels are (rows, cols), edge-padded outside."""
    h, w = image.shape
    o = np.arange(size)
    r = np.clip(rows[:, None, None] + o[None, :, None], 0, h - 1)
    c = np.clip(cols[:, None, None] + o[None, None, :], 0, w - 1)
    return image[r, c]


def _window_sums(a: np.ndarray, s: int) -> np.ndarray:
    """Σ over every s × s patch of each (n, m, m) array: (n, m − s + 1, m − s + 1)."""
    c = np.zeros((a.shape[0], a.shape[1] + 1, a.shape[2] + 1))
    c[:, 1:, 1:] = a.cumsum(1).cumsum(2)
    return c[:, s:, s:] - c[:, :-s, s:] - c[:, s:, :-s] + c[:, :-s, :-s]


def integer_seeds(ref: np.ndarray, cur: np.ndarray, cx: np.ndarray, cy: np.ndarray, half: int,
                  guess_u: np.ndarray, guess_v: np.ndarray, radius: int) -> tuple[np.ndarray, ...]:
    """(u, v, zncc) for subsets of half-width ``half`` centred at integer (cx, cy) of ``ref``:
    the integer displacement within ``radius`` px of the integer guess maximising the ZNCC."""
    s = 2 * half + 1
    m = s + 2 * radius
    n_fft = sfft.next_fast_len(m, real=True)
    u = np.zeros(cx.size)
    v = np.zeros(cx.size)
    score = np.zeros(cx.size)
    gu, gv = np.rint(guess_u).astype(int), np.rint(guess_v).astype(int)
    for a in range(0, cx.size, CHUNK):
        b = min(cx.size, a + CHUNK)
        t = _patches(ref, cy[a:b] - half, cx[a:b] - half, s)
        t = t - t.mean(axis=(1, 2), keepdims=True)
        tnorm = np.sqrt((t * t).sum(axis=(1, 2)))
        w = _patches(cur, cy[a:b] + gv[a:b] - half - radius, cx[a:b] + gu[a:b] - half - radius, m)
        spec = sfft.rfft2(w, (n_fft, n_fft)) * np.conj(sfft.rfft2(t, (n_fft, n_fft)))
        corr = sfft.irfft2(spec, (n_fft, n_fft))[:, : 2 * radius + 1, : 2 * radius + 1]
        s1, s2 = _window_sums(w, s), _window_sums(w * w, s)
        spread = np.sqrt(np.maximum(s2 - s1 * s1 / (s * s), 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            zncc = corr / (tnorm[:, None, None] * spread)
        zncc = np.where(np.isfinite(zncc), zncc, -np.inf)
        flat = zncc.reshape(b - a, -1)
        best = flat.argmax(axis=1)
        k, l = np.divmod(best, 2 * radius + 1)
        v[a:b] = gv[a:b] + k - radius
        u[a:b] = gu[a:b] + l - radius
        score[a:b] = flat[np.arange(b - a), best]
    return u, v, score
