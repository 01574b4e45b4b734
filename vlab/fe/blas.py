"""Thread limits for the short dense products of the element kernels."""

from __future__ import annotations

import contextlib

import vlab

_BLAS: list = []
NUMPY_BLAS = ["openblas", "blis"]  # the BLAS builds numpy wheels ship (MKL only with PARDISO)


def _controller():
    if not _BLAS:
        try:
            from threadpoolctl import ThreadpoolController
            _BLAS.append(ThreadpoolController())
        except ImportError:
            _BLAS.append(None)
    return _BLAS[0]


def serial_openblas() -> None:
    """Limit numpy's OpenBLAS to one thread for the rest of the process (PARDISO in use).

    OpenBLAS worker threads busy-wait after every threaded call (a vector norm or dot of a few
    10⁴ entries is enough); on 2 cores they then take a core from MKL's factorization, which
    runs single-threaded at ~1.7× the time (measured: 31 ms vs 50–60 ms, alternating, per
    factorization of the 21k-DOF dogbone). vlab's own dense products are short and serial."""
    controller = None if vlab.SERIAL_BLAS else _controller()
    if controller is not None:
        controller.select(internal_api=NUMPY_BLAS).limit(limits=1)


def single_threaded_blas():
    """Context limiting numpy's BLAS to one thread (threadpoolctl, if installed).

    The element GEMMs are short; BLAS worker threads that keep spinning after them steal the
    cores from the sparse factorization that follows (2× slower iterations measured on 2 cores).
    """
    controller = None if vlab.SERIAL_BLAS else _controller()
    if controller is None:
        return contextlib.nullcontext()
    # only numpy's own BLAS: limiting "blas" as a whole would also reset MKL, whose threads
    # PARDISO uses, on every call
    return controller.select(internal_api=NUMPY_BLAS).limit(limits=1)
