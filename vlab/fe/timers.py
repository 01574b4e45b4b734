"""Wall-clock time per solver phase (assembly, linear solves), gathered without changing results.

A run opens ``phase_clock()``; functions decorated with ``@timed("phase")`` add their wall time
to the innermost open clock of the current thread/context, and do nothing (one ContextVar lookup)
when none is open. Time is *exclusive*: a timed call nested in another timed call is charged to its
own phase only, so the phase totals never double count and add up to at most the run's time.
"""

from __future__ import annotations

import functools
import time
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Iterator

ASSEMBLY, LINEAR_SOLVE = "assembly", "linear_solve"


class PhaseClock:
    """Seconds and call counts per phase; a stack of open phases for exclusive timing."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self.calls: dict[str, int] = {}
        self._children: list[float] = []  # time spent in nested timed calls, per open phase

    def as_timing(self) -> dict[str, float]:
        """``{"<phase>_s": seconds}`` in the naming of RunResult.timing."""
        return {f"{phase}_s": s for phase, s in self.seconds.items()}


_current: ContextVar[PhaseClock | None] = ContextVar("vlab_phase_clock", default=None)


@contextmanager
def phase_clock() -> Iterator[PhaseClock]:
    """Collect the timed phases run inside the block (nested clocks each see their own)."""
    clock = PhaseClock()
    token = _current.set(clock)
    try:
        yield clock
    finally:
        _current.reset(token)


def timed(phase: str):
    """Decorator: charge the wrapped call's exclusive wall time to ``phase`` of the open clock."""
    def decorate(fn):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            clock = _current.get()
            if clock is None:
                return fn(*args, **kwargs)
            clock._children.append(0.0)
            start = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                elapsed = time.perf_counter() - start
                nested = clock._children.pop()
                clock.seconds[phase] = clock.seconds.get(phase, 0.0) + elapsed - nested
                clock.calls[phase] = clock.calls.get(phase, 0) + 1
                if clock._children:
                    clock._children[-1] += elapsed
        return wrapper
    return decorate
