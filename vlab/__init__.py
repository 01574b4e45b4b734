"""vlab: a virtual material-testing lab.

Data flow: scene (TOML) -> geometry (mesh with named regions) -> fe (Newton on the total
energy) -> measure (load cell, extensometers, E and nu) -> report (CSV, JSON, PNG, HTML).
"""

import os as _os
import sys as _sys

# numpy's OpenBLAS threads busy-wait after each threaded call and then take a core from the
# sparse factorization (MKL PARDISO runs ~1.7x slower on 2 cores, measured); vlab's dense
# products are short, so numpy's BLAS runs serial. Only effective before numpy loads; later,
# vlab.fe.blas.serial_openblas limits it at run time when PARDISO is loaded.
if "numpy" not in _sys.modules:
    _os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
#: True when numpy's BLAS is known to be serial for the whole process (no run-time limit needed).
SERIAL_BLAS = "numpy" not in _sys.modules and _os.environ.get("OPENBLAS_NUM_THREADS") == "1"

__version__ = "0.1.0"


_API = {"Scene": "vlab.api", "Result": "vlab.api", "Curve": "vlab.api", "SceneError": "vlab.scene"}


def __getattr__(name: str):
    """vlab.Scene, vlab.Result, vlab.Curve, vlab.SceneError, loaded on first use (importing vlab
    stays light: no solver, no numba)."""
    if name in _API:
        import importlib

        return getattr(importlib.import_module(_API[name]), name)
    raise AttributeError(f"module 'vlab' has no attribute {name!r}")
