"""Wall-clock time and peak memory per solver phase, gathered without changing results.

A run opens ``phase_clock()``; functions decorated with ``@timed("phase")`` add their wall time
to the innermost open clock of the current thread/context, and do nothing (one ContextVar lookup)
when none is open. Time is *exclusive*: a timed call nested in another timed call is charged to its
own phase only, so the phase totals never double count and add up to at most the run's time.
``memory_phase(name)`` marks a stretch of code for memory only (no time booked).

Peak memory per phase (``PhaseClock.peak_memory_mb``) is the process's resident set size (RSS,
everything the process holds, not only what the phase allocated) at its highest while that phase
was the innermost open one, from two sources:
- the kernel's high-water mark (getrusage ru_maxrss): when it rose while the phase ran, the new
  process peak happened inside the phase, and that value is exact;
- otherwise a sampler thread reading the RSS every SAMPLE_S (psutil): a lower bound that can miss
  a transient shorter than the interval (or one inside a long call that holds the GIL).
``run`` is the process's high-water mark when the clock closes (including what came before it).
"""

from __future__ import annotations

import functools
import resource
import threading
import time
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Iterator

ASSEMBLY, LINEAR_SOLVE, STABILITY = "assembly", "linear_solve", "stability_check"


class PhaseClock:
    """Seconds and call counts per phase; a stack of open phases for exclusive timing."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self.calls: dict[str, int] = {}
        self._children: list[float] = []  # time spent in nested timed calls, per open phase
        self._open: list[tuple[str, int]] = []  # (phase, ru_maxrss at entry), innermost last
        self.peak_bytes: dict[str, int] = {}

    def as_timing(self) -> dict[str, float]:
        """``{"<phase>_s": seconds}`` in the naming of RunResult.timing."""
        return {f"{phase}_s": s for phase, s in self.seconds.items()}

    @property
    def peak_memory_mb(self) -> dict[str, float]:
        """Peak RSS per phase in MB (module docstring), ``run`` for the whole process."""
        return {phase: round(b / 1e6, 1) for phase, b in self.peak_bytes.items()}

    def enter(self, phase: str) -> None:
        self._open.append((phase, _high_water()))

    def leave(self) -> None:
        phase, before = self._open.pop()
        now = _high_water()
        if now > before:  # the process peak rose inside this phase: exact
            self._book(phase, now)
        elif phase not in self.peak_bytes:  # a phase too short for a sample: its RSS at the end
            self._book(phase, _rss())

    def sample(self, rss: int) -> None:
        try:  # (the main thread may pop the list meanwhile)
            phase = self._open[-1][0]
        except IndexError:
            phase = "other"
        self._book(phase, rss)

    def _book(self, phase: str, rss: int) -> None:
        if rss > self.peak_bytes.get(phase, 0):
            self.peak_bytes[phase] = rss


SAMPLE_S = 0.005


def _rss() -> int:
    """The resident set size now, bytes (/proc/self/statm: pages)."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * resource.getpagesize()
    except OSError:
        return 0


def _high_water() -> int:
    """The process's peak RSS so far, bytes (Linux reports ru_maxrss in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


_current: ContextVar[PhaseClock | None] = ContextVar("vlab_phase_clock", default=None)


@contextmanager
def phase_clock() -> Iterator[PhaseClock]:
    """Collect the timed phases run inside the block (nested clocks each see their own)."""
    clock = PhaseClock()
    token = _current.set(clock)
    stop = threading.Event()
    sampler = threading.Thread(target=_sample, args=(clock, stop), daemon=True)
    sampler.start()
    try:
        yield clock
    finally:
        stop.set()
        sampler.join()
        # (the kernel's per-thread RSS counters lag by a few pages: the run peak is the larger)
        clock.peak_bytes["run"] = max([_high_water(), *clock.peak_bytes.values()])
        _current.reset(token)


def _sample(clock: PhaseClock, stop: threading.Event) -> None:
    import psutil

    process = psutil.Process()
    while not stop.wait(SAMPLE_S):
        clock.sample(process.memory_info().rss)


@contextmanager
def memory_phase(name: str) -> Iterator[None]:
    """Attribute the memory of the block to ``name`` (no time is booked)."""
    clock = _current.get()
    if clock is None:
        yield
        return
    clock.enter(name)
    try:
        yield
    finally:
        clock.leave()


def timed(phase: str):
    """Decorator: charge the wrapped call's exclusive wall time to ``phase`` of the open clock."""
    def decorate(fn):
        @functools.wraps(fn)
        def wrapper(*args, **kwargs):
            clock = _current.get()
            if clock is None:
                return fn(*args, **kwargs)
            clock._children.append(0.0)
            clock.enter(phase)
            start = time.perf_counter()
            try:
                return fn(*args, **kwargs)
            finally:
                elapsed = time.perf_counter() - start
                clock.leave()
                nested = clock._children.pop()
                clock.seconds[phase] = clock.seconds.get(phase, 0.0) + elapsed - nested
                clock.calls[phase] = clock.calls.get(phase, 0) + 1
                if clock._children:
                    clock._children[-1] += elapsed
        return wrapper
    return decorate
