"""Intel MKL PARDISO through ctypes: sparse Cholesky (LLᵀ) and Bunch–Kaufman LDLᵀ with the
symbolic analysis reused across factorizations of one sparsity pattern.

PARDISO is an optional extra (``pip install vlab[fast]`` pulls ``pypardiso`` and the ``mkl``
wheel that ships ``mkl_rt``); vlab loads that library and calls ``pardiso`` itself so it can
separate the phases:

- phase 11 (reordering with METIS nested dissection + symbolic factorization) once per pattern,
- phase 22 (numerical factorization) once per tangent, into one of ``SLOTS`` factor slots that
  share the analysis (PARDISO's ``maxfct``/``mnum``), so the predictor's tangent survives the
  next Newton iterations,
- phase 33 (forward/backward substitution) per right-hand side.

Only the upper triangle of the symmetric matrix is passed (CSR, 1-based indices). ``mtype = 2``
(real SPD, Cholesky) is tried first; if PARDISO meets a non-positive pivot (error -4) the pattern
switches to ``mtype = -2`` (real symmetric indefinite, Bunch–Kaufman pivoting with pivot
perturbation), whose inertia (iparm 22/23: positive/negative eigenvalue counts by Sylvester's law)
is reported as ``negative_pivots``.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import glob
import logging
import os
import site
import sys
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from vlab.fe.blas import serial_openblas

log = logging.getLogger(__name__)

SLOTS = 2
SPD, INDEFINITE = 2, -2
_ERRORS = {-1: "input inconsistent", -2: "not enough memory", -3: "reordering problem",
           -4: "zero pivot (numerical factorization)", -5: "unclassified internal error",
           -6: "reordering failed", -7: "diagonal matrix is singular", -8: "32-bit integer overflow",
           -9: "not enough memory for out-of-core", -10: "problems opening OOC files",
           -11: "read/write problem with OOC data file", -12: "pardiso_64 called from 32-bit library"}


@dataclass(frozen=True)
class FactorCost:
    """What PARDISO's analysis (phase 11: METIS ordering, symbolic factorization) predicts for
    every numerical factorization of one sparsity pattern, before any is made."""

    factor_nonzeros: int  # entries of the Cholesky factor L (iparm(18))
    mflops: int  # 10⁶ floating-point operations of one numerical factorization (iparm(19))
    matrix_nonzeros: int  # stored entries of the full symmetric matrix (both triangles)

    @property
    def flops_per_nonzero(self) -> float:
        """Factorization flops per stored entry of K: a CG iteration costs O(1) per entry (the
        matrix-vector product and the V-cycle's smoothing), so this ratio, not the DOF count, says
        how many CG iterations one factorization is worth (vlab.fe.iterative.decide)."""
        return 1e6 * self.mflops / max(self.matrix_nonzeros, 1)

    @property
    def factor_bytes(self) -> int:
        return 8 * self.factor_nonzeros

    def of_blocks(self, b: int) -> "FactorCost":
        """The cost for the matrix whose every entry of this one's pattern is a b × b block (a
        node graph → its b DOFs per node): b² entries each, in K and in L, and b³ flops per
        scalar flop of the factorization's dense kernels."""
        return FactorCost(self.factor_nonzeros * b * b, self.mflops * b**3, self.matrix_nonzeros * b * b)


class PardisoError(RuntimeError):
    def __init__(self, code: int, phase: int):
        super().__init__(f"PARDISO phase {phase} error {code}: {_ERRORS.get(code, 'unknown')}")
        self.code = code


_LIB: list = []  # [ctypes function] once loaded, [None] if unavailable


def library():
    """The ``pardiso`` entry point of MKL's runtime, or None if the mkl wheel is not installed.

    ``mkl_rt`` is looked up where the mkl wheel puts it (``<prefix>/lib``) before falling back to
    pypardiso's own (slow, recursive) search."""
    if not _LIB:
        _LIB.append(_load())
        if _LIB[0] is not None:
            serial_openblas()
    return _LIB[0]


def _load():
    # MKL's OpenMP workers spin for 200 ms after each call (its default, read when the runtime
    # starts). numpy's BLAS is serial in vlab, so a spinning worker only holds a core the
    # assembly does not use, and the next factorization or solve starts without waking threads:
    # measured against KMP_BLOCKTIME=0, block8 0.31 -> 0.24 s, block16 3.0 -> 2.8 s per run.
    os.environ.setdefault("KMP_BLOCKTIME", "200")
    def candidates():
        yield os.environ.get("PYPARDISO_MKL_RT")
        for prefix in dict.fromkeys((sys.prefix, site.getuserbase())):
            yield from sorted(glob.glob(os.path.join(prefix, "lib", "libmkl_rt.so*")), key=len)
            yield from sorted(glob.glob(os.path.join(prefix, "Library", "bin", "mkl_rt*.dll")), key=len)
        yield ctypes.util.find_library("mkl_rt")  # last: it runs ldconfig/gcc (~25 ms)

    for path in filter(None, candidates()):
        try:
            fn = ctypes.CDLL(path).pardiso
        except (OSError, AttributeError):
            continue
        fn.restype = None
        return fn
    try:
        from pypardiso.pardiso_wrapper import PyPardisoSolver

        fn = PyPardisoSolver().libmkl.pardiso
        fn.restype = None
        return fn
    except Exception as exc:  # ImportError, OSError: missing wheel or library
        log.debug("PARDISO unavailable: %s", exc)
        return None


def version() -> str | None:
    try:
        from importlib.metadata import version as dist_version
        return f"MKL PARDISO (mkl {dist_version('mkl')})"
    except Exception:
        return None


@dataclass
class _Handle:
    """One PARDISO internal data structure (``pt``) with its analysis for one matrix type."""

    mtype: int
    n: int
    pt: np.ndarray = field(default_factory=lambda: np.zeros(64, dtype=np.int64))
    iparm: np.ndarray = field(default_factory=lambda: np.zeros(64, dtype=np.int32))
    analysed: bool = False

    def __post_init__(self):
        ip = self.iparm
        ip[0] = 1     # iparm(1): use the values below, not the defaults
        ip[1] = 2     # iparm(2): METIS nested-dissection ordering
        # iparm(8): iterative refinement. A Cholesky solve is backward stable without it
        # (relative residual 2e-15 measured on the 16³ block) and 2–2.7× faster; the indefinite
        # LDLᵀ keeps up to two steps, which pivot perturbation needs.
        ip[7] = 0 if self.mtype == SPD else 2
        ip[9] = 8     # iparm(10): pivot perturbation 1e-8 (symmetric matrices)
        ip[10] = 0    # iparm(11): no scaling (symmetric)
        ip[12] = 0    # iparm(13): no weighted matching (symmetric)
        ip[20] = 1    # iparm(21): Bunch–Kaufman 1x1 and 2x2 pivots (indefinite)
        ip[34] = 0    # iparm(35): 1-based indexing

    def call(self, phase: int, slot: int, matrix, rhs: np.ndarray | None = None) -> np.ndarray | None:
        data, ia, ja = matrix
        b = np.zeros(1) if rhs is None else np.asfortranarray(rhs, dtype=float)
        x = np.zeros_like(b)
        err = ctypes.c_int32(0)
        i32 = ctypes.POINTER(ctypes.c_int32)
        f64 = ctypes.POINTER(ctypes.c_double)
        nrhs = 1 if b.ndim == 1 else b.shape[1]
        library()(self.pt.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)),
                  ctypes.byref(ctypes.c_int32(SLOTS)), ctypes.byref(ctypes.c_int32(slot + 1)),
                  ctypes.byref(ctypes.c_int32(self.mtype)), ctypes.byref(ctypes.c_int32(phase)),
                  ctypes.byref(ctypes.c_int32(self.n)), data.ctypes.data_as(f64),
                  ia.ctypes.data_as(i32), ja.ctypes.data_as(i32), None,
                  ctypes.byref(ctypes.c_int32(nrhs)), self.iparm.ctypes.data_as(i32),
                  ctypes.byref(ctypes.c_int32(0)), b.ctypes.data_as(f64), x.ctypes.data_as(f64),
                  ctypes.byref(err))
        if err.value != 0:
            raise PardisoError(err.value, phase)
        return x if rhs is not None else None

    def release(self, matrix) -> None:
        if self.analysed and library() is not None:
            try:
                self.call(-1, 0, matrix)
            except PardisoError:  # pragma: no cover - freeing never fails in practice
                pass
            self.analysed = False


class PardisoPattern:
    """Everything PARDISO keeps for one symmetric sparsity pattern: the upper-triangle gather,
    the analysis (per matrix type), and ``SLOTS`` numerical factors used least-recently first."""

    def __init__(self, K: sp.csr_matrix):
        n = K.shape[0]
        row = np.repeat(np.arange(n), np.diff(K.indptr))
        self.upper = np.flatnonzero(K.indices >= row)
        counts = np.bincount(row[self.upper], minlength=n)
        self.ia = np.r_[0, np.cumsum(counts)].astype(np.int32) + 1
        self.ja = K.indices[self.upper].astype(np.int32) + 1
        if np.any(counts == 0) or np.any(self.ja[self.ia[:-1] - 1] - 1 != np.arange(n)):
            raise ValueError("PARDISO needs every diagonal entry stored (sorted symmetric pattern)")
        self.n = n
        self.handle = _Handle(SPD, n)
        self.owner: list[object | None] = [None] * SLOTS  # which factorization holds each slot
        self.clock = [0] * SLOTS
        self.tick = 0

    def upper_values(self, K: sp.csr_matrix) -> np.ndarray:
        return np.ascontiguousarray(K.data[self.upper], dtype=float)

    def factor_into_slot(self, owner: object, values: np.ndarray) -> int:
        """Numerically factorize ``values`` (upper triangle) into the least recently used slot."""
        slot = int(np.argmin(self.clock))
        matrix = (values, self.ia, self.ja)
        try:
            self._factor(slot, matrix)
        except PardisoError as exc:
            if exc.code != -4 or self.handle.mtype != SPD:
                raise
            log.debug("tangent not positive definite: switching to Bunch–Kaufman LDLᵀ")
            self.handle.release(matrix)
            self.handle = _Handle(INDEFINITE, self.n)
            self.owner = [None] * SLOTS
            self._factor(slot, matrix)
        self.owner[slot] = owner
        self.tick += 1
        self.clock[slot] = self.tick
        return slot

    def predicted_cost(self, values: np.ndarray) -> FactorCost:
        """The analysis's prediction (FactorCost), the analysis kept for the factorizations to
        come; ``values`` (upper triangle) are not read by an SPD analysis without scaling or
        matching, only the pattern is."""
        if self._cost is None:
            ip = self.handle.iparm
            ip[17], ip[18] = -1, -1  # report nnz(L) and the factorization's MFLOP count
            self.handle.call(11, 0, (values, self.ia, self.ja))
            if self.handle.analysed:  # a new analysis voids the factors made on the old one
                self.owner = [None] * SLOTS
            self.handle.analysed = True
            self._cost = FactorCost(int(ip[17]), int(ip[18]), 2 * len(self.ja) - self.n)
        return self._cost

    _cost: FactorCost | None = None

    def _factor(self, slot: int, matrix) -> None:
        if not self.handle.analysed:
            self.handle.call(11, 0, matrix)
            self.handle.analysed = True
        self.handle.call(22, slot, matrix)

    def solve(self, slot: int, values: np.ndarray, b: np.ndarray) -> np.ndarray:
        self.tick += 1
        self.clock[slot] = self.tick
        return self.handle.call(33, slot, (values, self.ia, self.ja), b)

    @property
    def negative_pivots(self) -> int:
        """Negative eigenvalues of the last factorized matrix (0 for a successful Cholesky)."""
        return 0 if self.handle.mtype == SPD else int(self.handle.iparm[22])

    def __del__(self):
        try:
            self.handle.release((np.zeros(1), self.ia, self.ja))
        except Exception:  # pragma: no cover - interpreter shutdown
            pass
