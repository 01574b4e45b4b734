"""Exact parameter derivatives by the complex step.

For a real-analytic f, f(x + i h e_j) = f(x) + i h ∂f/∂x_j − h²/2 ∂²f/∂x_j² + O(h³), so
∂f/∂x_j = Im f(x + i h e_j) / h with no subtractive cancellation: with h = 1e-30 the truncation
error (h²) is far below round-off and the derivative is exact to machine precision. Every
response in vlab.identify is written with analytic numpy operations (and its Newton solves run
in complex arithmetic), so one vectorised evaluation at the n_x + 1 points [x, x + i h e_1, …]
gives the prediction and its whole Jacobian.
"""

from __future__ import annotations

import numpy as np

__all__ = ["value_and_jacobian", "H"]

H = 1e-30


def value_and_jacobian(f, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(f(x), ∂f/∂x) of f: (m, n_x) -> (m, n) at one real x (n_x,): shapes (n,), (n, n_x)."""
    x = np.asarray(x, float)
    X = np.tile(x.astype(complex), (len(x) + 1, 1))
    X[1:] += 1j * H * np.eye(len(x))
    Y = f(X)
    return np.real(Y[0]), (np.imag(Y[1:]) / H).T
