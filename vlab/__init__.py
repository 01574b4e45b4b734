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


_API = {"Scene": "vlab.api", "Result": "vlab.api", "Curve": "vlab.api", "SceneError": "vlab.scene",
        "fit": "vlab.api_fit", "Fit": "vlab.api_fit", "Ranking": "vlab.api_fit",
        "sweep": "vlab.api_studies", "Sweep": "vlab.api_studies", "cost": "vlab.api_studies",
        "CostStudy": "vlab.api_studies", "Comparison": "vlab.api_compare",
        "stability": "vlab.api_checks", "Stability": "vlab.api_checks", "Export": "vlab.api_checks"}
#: the API's commands whose name is also a module of the package (vlab/compare.py, vlab/export/): the
#: module itself is callable (vlab.compare(...) runs the command, vlab.compare.compare_models stays)
_COMMAND_MODULES = {"vlab.compare": ("vlab.api_compare", "compare"), "vlab.export": ("vlab.api_checks", "export")}


class _CommandModule(type(_os)):
    """A module that is also a command of the Python API (see _COMMAND_MODULES)."""

    def __call__(self, *args, **kwargs):
        import importlib

        module, name = _COMMAND_MODULES[self.__name__]
        return getattr(importlib.import_module(module), name)(*args, **kwargs)


def _command_module(name: str) -> None:
    """Called by vlab.compare and vlab.export as they load: make the module callable."""
    _sys.modules[name].__class__ = _CommandModule


def __getattr__(name: str):
    """vlab.Scene, vlab.Result, vlab.Curve, vlab.SceneError and the commands vlab.fit, vlab.compare,
    vlab.sweep, vlab.cost, vlab.stability, vlab.export (with their result classes), loaded on first
    use (importing vlab stays light: no solver, no numba)."""
    import importlib

    if name in _API:
        return getattr(importlib.import_module(_API[name]), name)
    if f"vlab.{name}" in _COMMAND_MODULES:
        return importlib.import_module(f"vlab.{name}")
    raise AttributeError(f"module 'vlab' has no attribute {name!r}")
