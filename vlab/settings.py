"""Process-wide switches in one object: the assembly kernel, its thread count, the direct solver.

    kernel            "auto" (compiled numba kernels where they apply) | "numpy"   VLAB_KERNEL
    assembly_threads  1..the cores numba may use; None = numba's own count        VLAB_ASSEMBLY_THREADS
    linear_solver     "auto" (PARDISO if installed) | "pardiso" | "superlu"       VLAB_LINEAR_SOLVER
    iterative_from    free DOFs from which solver.linear = "auto" takes CG + AMG   VLAB_ITERATIVE_FROM
                      and the LOBPCG stability check (None: the measured crossover of
                      vlab.fe.iterative; 0 forces the iterative path on any 3D mesh)
    figure_process    "auto" (a `vlab run` draws its report's figures in a second    VLAB_FIGURE_PROCESS
                      process unless matplotlib is already imported) | "on" | "off"
                      (vlab.report.figure_worker)

:meth:`Settings.from_environment` reads (and validates) the variables; the CLI fills the object
from them at start-up and installs it with :func:`use`, vlab compare's worker processes install
a copy with one assembly thread each, and ``run_scene(..., settings=...)`` runs under the given
settings. The solver's modules read the installed one through :func:`current` (the environment
is read once, lazily, when nothing was installed), never the environment directly.
"""

from __future__ import annotations

import contextlib
import os
from dataclasses import dataclass
from typing import Iterator, Mapping

__all__ = ["Settings", "current", "use", "using"]

KERNELS = ("auto", "numpy")
LINEAR_SOLVERS = ("auto", "pardiso", "superlu")
FIGURE_PROCESS = ("auto", "on", "off")


@dataclass(frozen=True)
class Settings:
    kernel: str = "auto"
    assembly_threads: int | None = None
    linear_solver: str = "auto"
    iterative_from: int | None = None
    figure_process: str = "auto"

    def __post_init__(self) -> None:
        if self.figure_process not in FIGURE_PROCESS:
            raise ValueError(f"VLAB_FIGURE_PROCESS must be one of {', '.join(FIGURE_PROCESS)}; "
                             f"got {self.figure_process!r}")
        if self.kernel not in KERNELS:
            raise ValueError(f"VLAB_KERNEL must be one of {', '.join(KERNELS)}; got {self.kernel!r}")
        if self.linear_solver not in LINEAR_SOLVERS:
            raise ValueError(f"VLAB_LINEAR_SOLVER must be one of {', '.join(LINEAR_SOLVERS)}; "
                             f"got {self.linear_solver!r}")
        if self.iterative_from is not None and not self.iterative_from >= 0:
            raise ValueError(f"VLAB_ITERATIVE_FROM must be a number of free DOFs ≥ 0; got {self.iterative_from!r}")
        most = usable_cores()
        if self.assembly_threads is not None and not 1 <= self.assembly_threads <= most:
            raise ValueError(f"VLAB_ASSEMBLY_THREADS must be an integer from 1 to {most} (the cores "
                             f"numba may use); got {self.assembly_threads!r}")

    @classmethod
    def from_environment(cls, environ: Mapping[str, str] = os.environ) -> "Settings":
        """The switches as the environment sets them; ValueError naming a bad variable."""
        threads = environ.get("VLAB_ASSEMBLY_THREADS", "").strip()
        if threads and not threads.isdigit():
            raise ValueError(f"VLAB_ASSEMBLY_THREADS must be an integer from 1 to {usable_cores()} (the "
                             f"cores numba may use); got {threads!r}")
        start = environ.get("VLAB_ITERATIVE_FROM", "").strip()
        if start and not start.isdigit():
            raise ValueError(f"VLAB_ITERATIVE_FROM must be a number of free DOFs ≥ 0; got {start!r}")
        return cls(kernel=environ.get("VLAB_KERNEL", "auto").strip().lower() or "auto",
                   assembly_threads=int(threads) if threads else None,
                   iterative_from=int(start) if start else None,
                   linear_solver=environ.get("VLAB_LINEAR_SOLVER", "auto").strip().lower() or "auto",
                   figure_process=environ.get("VLAB_FIGURE_PROCESS", "auto").strip().lower() or "auto")


def usable_cores(environ: Mapping[str, str] = os.environ) -> int:
    """The cores numba may use: NUMBA_NUM_THREADS if set, else this process's CPU affinity."""
    cores = (len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")  # Linux only
             else os.cpu_count() or 1)
    return int(environ.get("NUMBA_NUM_THREADS", "").strip() or cores)


_INSTALLED: list[Settings] = []


def current() -> Settings:
    """The installed settings (read from the environment on first use if none were installed)."""
    if not _INSTALLED:
        _INSTALLED.append(Settings.from_environment())
    return _INSTALLED[0]


def use(settings: Settings) -> None:
    """Install ``settings`` for the rest of the process."""
    _INSTALLED[:] = [settings]


@contextlib.contextmanager
def using(settings: Settings | None) -> Iterator[Settings]:
    """Install ``settings`` for the duration of a block (None: keep the current ones)."""
    previous = current()
    if settings is not None:
        use(settings)
    try:
        yield current()
    finally:
        use(previous)
