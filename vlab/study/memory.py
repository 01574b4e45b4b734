"""Peak resident memory of the current process over a block of code.

Linux: the kernel's high-water mark of the resident set (VmHWM) is reset by writing "5" to
/proc/self/clear_refs before the block, then read with ``resource.getrusage(RUSAGE_SELF).ru_maxrss``
after it (kB): the exact peak of this process during the block, at no cost while it runs.
Elsewhere (or where the reset is refused) a psutil thread samples the RSS every 5 ms: a lower bound
that can miss spikes shorter than the sampling period. ``method`` says which was used. tracemalloc
is not used: it slows numpy-heavy code several fold and sees only Python allocations.
"""

from __future__ import annotations

import resource
import sys
import threading
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Iterator

import psutil

MB = 1024.0**2
SAMPLE_PERIOD_S = 0.005


@dataclass
class PeakMemory:
    baseline_mb: float = 0.0  # RSS when the block started
    peak_mb: float = 0.0  # highest RSS during the block (includes the baseline)
    method: str = ""

    def as_dict(self) -> dict:
        return {"peak_rss_mb": self.peak_mb, "baseline_rss_mb": self.baseline_mb,
                "increase_mb": max(0.0, self.peak_mb - self.baseline_mb), "method": self.method}


def _reset_high_water_mark() -> bool:
    if not sys.platform.startswith("linux"):
        return False
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


@contextmanager
def peak_memory() -> Iterator[PeakMemory]:
    """Measure the peak RSS of this process while the block runs (see the module docstring)."""
    process = psutil.Process()
    record = PeakMemory(baseline_mb=process.memory_info().rss / MB)
    if _reset_high_water_mark():
        record.method = "VmHWM reset via /proc/self/clear_refs, read by getrusage ru_maxrss"
        try:
            yield record
        finally:
            record.peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        return
    record.method = f"psutil RSS sampled every {SAMPLE_PERIOD_S * 1e3:g} ms (lower bound)"
    stop = threading.Event()
    peak = [record.baseline_mb]

    def sample():
        while not stop.wait(SAMPLE_PERIOD_S):
            peak[0] = max(peak[0], process.memory_info().rss / MB)

    thread = threading.Thread(target=sample, daemon=True)
    thread.start()
    try:
        yield record
    finally:
        stop.set()
        thread.join()
        record.peak_mb = max(peak[0], process.memory_info().rss / MB)
