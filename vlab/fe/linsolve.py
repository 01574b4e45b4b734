"""Sparse direct solves for the Newton systems K_ff Δu = -r.

SuperLU (scipy) in symmetric mode is the solver that always installs. With a minimum-degree
ordering on A + Aᵀ and no partial pivoting it behaves like an LDLᵀ factorization for the
symmetric tangents assembled here; if a zero pivot appears (singular or indefinite pattern) the
factorization is retried with threshold pivoting.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


class SingularSystem(RuntimeError):
    """The tangent has no usable factorization (rigid-body mode or collapsed element)."""


class Factorization:
    """A factorized sparse matrix; ``solve`` applies its inverse."""

    def __init__(self, K: sp.spmatrix):
        K = sp.csc_matrix(K)
        try:
            self._lu = spla.splu(K, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                 options={"SymmetricMode": True})
        except RuntimeError:
            try:
                self._lu = spla.splu(K)
            except RuntimeError as exc:
                raise SingularSystem(f"sparse factorization failed: {exc}") from exc
        self.shape = K.shape

    def solve(self, b: np.ndarray) -> np.ndarray:
        x = self._lu.solve(np.asarray(b, dtype=float))
        if not np.all(np.isfinite(x)):
            raise SingularSystem("the solve produced non-finite values (singular tangent)")
        return x


def factorize(K: sp.spmatrix) -> Factorization:
    return Factorization(K)
