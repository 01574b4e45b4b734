"""The report's libraries imported in a background thread while the solver works.

A run's report imports matplotlib (figure, Agg backend, ticker: 0.4-0.5 CPU-s, its Artist classes
build their property docstrings at import) only after the solve. The solver spends most of its time in code that releases
the GIL (PARDISO through ctypes, the numba kernels are ``nogil``), so the same imports made by a
thread started at the first converged load level cost the command little wall time
(benchmarks/command_overhead.py). Only third-party modules are imported here (no vlab module,
whose lazy imports the solving thread may be making at the same moment); a failed import is
left to the report writer, which imports the same modules and reports the error itself.
"""

from __future__ import annotations

import importlib
import threading

MODULES = ("matplotlib.figure", "matplotlib.backends.backend_agg", "matplotlib.ticker")


def _import_all(modules: tuple[str, ...]) -> None:
    for name in modules:
        try:
            importlib.import_module(name)
        except Exception:  # noqa: BLE001 - the writer imports it again and reports the error
            return


class ReportPrefetch:
    """``on_level(callback)`` wraps a run's level callback so that the first level starts the
    import thread; ``wait()`` joins it before the report is written."""

    def __init__(self, modules: tuple[str, ...] = MODULES):
        self.thread = threading.Thread(target=_import_all, args=(modules,), name="vlab-report-imports",
                                       daemon=True)

    def on_level(self, callback=None):
        def level(*args, **kwargs):
            if self.thread.ident is None:
                self.thread.start()
            if callback is not None:
                return callback(*args, **kwargs)
        return level

    def wait(self) -> None:
        if self.thread.ident is not None:
            self.thread.join()
