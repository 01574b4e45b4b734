"""vlab: a virtual material-testing lab.

Data flow: scene (TOML) -> geometry (mesh with named regions) -> fe (Newton on the total
energy) -> measure (load cell, extensometers, E and nu) -> report (CSV, JSON, PNG, HTML).
"""

import os as _os
import sys as _sys

# numpy's OpenBLAS threads busy-wait after each threaded call and then take a core from the
# sparse factorization (MKL PARDISO runs ~1.7x slower on 2 cores, measured); vlab's dense
# products are short, so numpy's BLAS runs serial: limited at run time by vlab.fe.blas
# (threadpoolctl), or from the start by a program that owns its process (serial_blas_process).
# Importing vlab writes no environment variable.
#: True when numpy's BLAS is known to be serial for the whole process (no run-time limit needed).
SERIAL_BLAS = "numpy" not in _sys.modules and _os.environ.get("OPENBLAS_NUM_THREADS") == "1"


def serial_blas_process() -> None:
    """For a program that owns its process (the CLI, the benchmarks), called before numpy loads:
    OPENBLAS_NUM_THREADS=1 unless the user set it, so numpy's BLAS is serial from the start."""
    global SERIAL_BLAS
    if "numpy" not in _sys.modules:
        _os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
        SERIAL_BLAS = _os.environ["OPENBLAS_NUM_THREADS"] == "1"

__version__ = "0.1.0"


_API = {"Scene": "vlab.api", "Result": "vlab.api", "Curve": "vlab.api", "SceneError": "vlab.scene"}


def __getattr__(name: str):
    """vlab.Scene, vlab.Result, vlab.Curve, vlab.SceneError, loaded on first use (importing vlab
    stays light: no solver, no numba)."""
    if name in _API:
        import importlib

        return getattr(importlib.import_module(_API[name]), name)
    raise AttributeError(f"module 'vlab' has no attribute {name!r}")
