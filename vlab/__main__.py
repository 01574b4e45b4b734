"""``python -m vlab`` and the ``vlab`` console script: the CLI, then a fast process exit.

When the command has finished (its report renamed into place, its output printed), the process
ends with ``os._exit`` after flushing the standard streams and logging, running the ``atexit``
handlers and joining the non-daemon threads, i.e. without the interpreter's finalization:
tearing down numba/LLVM, MKL/OpenMP's thread pools, the PARDISO handle and every module cost
0.6-0.9 CPU-s (1-2 s of wall time on the loaded 2-core machine) after a ``vlab run`` of
benchmarks/block16.toml (benchmarks/RESULTS.md, "command overhead"), work whose only effect is
freeing memory the kernel frees anyway. Tests call ``vlab.cli.app`` through typer's runner and
keep the normal exit.
"""

from __future__ import annotations

import atexit
import logging
import os
import sys
import threading


def _exit_code(code) -> int:
    """SystemExit's code as a process status (None: 0; a message: printed, 1), as Python does."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code
    print(code, file=sys.stderr)
    return 1


def main() -> None:
    from vlab.cli import app

    try:
        app(prog_name="vlab")
        code = 0
    except SystemExit as exc:
        code = _exit_code(exc.code)
    _finish(code)


def _finish(code: int) -> None:
    """End the process as Python's exit would, less the interpreter's finalization."""
    shutdown = getattr(threading, "_shutdown", None)  # waits for non-daemon threads, as exit does
    if shutdown is not None:
        shutdown()
    atexit._run_exitfuncs()
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    main()
