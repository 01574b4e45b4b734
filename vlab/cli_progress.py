"""What the terminal shows while a command works: one live rich display (phase, load level,
Newton iterations, elapsed time) instead of a line per level, and warnings printed once each.
The library never prints; only the CLI builds these."""

from __future__ import annotations

import logging

from rich.console import Console
from rich.logging import RichHandler
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

RAMP_WIDTH = 30  # the description column: a phase or the ramp, so that 80 columns show the ramp whole


class OnceFilter(logging.Filter):
    """Lets each distinct message through once (a companion solve repeats the scene's warnings)."""

    def __init__(self):
        super().__init__()
        self.seen: set[str] = set()

    def filter(self, record: logging.LogRecord) -> bool:
        text = record.getMessage()
        if text in self.seen:
            return False
        self.seen.add(text)
        return True


def route_warnings(console: Console) -> None:
    """vlab's warnings to ``console`` (above any live display), each once per command."""
    logger = logging.getLogger("vlab")
    for handler in [h for h in logger.handlers if getattr(h, "_vlab_cli", False)]:
        logger.removeHandler(handler)
    handler = RichHandler(console=console, show_time=False, show_path=False, show_level=False,
                          markup=False, rich_tracebacks=False, highlighter=None)
    handler.setLevel(logging.WARNING)
    handler.addFilter(OnceFilter())
    handler._vlab_cli = True
    logger.addHandler(handler)  # still propagates: a caller's own handlers (pytest's caplog) see it too


def scheduled_levels(scene) -> int:
    """Load levels the scene's protocol schedules (cutbacks may add substeps, not levels)."""
    return sum(n for _, n in scheduled_ramps(scene))


def scheduled_ramps(scene) -> list[tuple[str, int]]:
    """The scene's levels as ramps: (name, levels) in order (vlab.loading.protocol's schedule)."""
    from vlab.loading.kinds import run_levels

    levels = run_levels(scene)
    return ramps_of(levels.t)


def ramps_of(t) -> list[tuple[str, int]]:
    """Consecutive levels with the same direction of the load factor t (from 0): "loading" where t
    rises, "unloading" where it falls, "hold" where it stays; with more than one loading ramp (a
    cyclic test) each is prefixed by its cycle, "cycle 2 loading"."""
    import numpy as np

    steps = np.sign(np.round(np.diff(np.concatenate([[0.0], np.asarray(t, dtype=float)])), 12)).astype(int)
    runs: list[list] = []
    for s in steps.tolist():
        if runs and runs[-1][0] == s:
            runs[-1][1] += 1
        else:
            runs.append([s, 1])
    names = {1: "loading", -1: "unloading", 0: "hold"}
    cycles = sum(1 for s, _ in runs if s == 1)
    cycle, out = 0, []
    for s, n in runs:
        cycle += s == 1
        prefix = f"cycle {cycle} " if cycles > 1 and s != 0 else ""
        out.append((prefix + names[s], n))
    return out


def ramp_text(ramps: list[tuple[str, int]], done: int, width: int = RAMP_WIDTH) -> str:
    """Where ``done`` levels are in the ramps: "loading 10/10, unloading 3/9" (the current ramp and
    the one before it, or only the current one where both exceed ``width`` characters)."""
    parts, start = [], 0
    for name, n in ramps:
        parts.append(f"{name} {min(done - start, n)}/{n}")
        start += n
        if done <= start:
            break
    both = ", ".join(parts[-2:])
    return both if len(both) <= width else parts[-1]


class RunProgress:
    """The live display of one `vlab run`: the set-up phase, then the ramp the levels are on
    ("loading 10/10, unloading 3/9"); levels done of scheduled; the last level's load factor t and
    Newton iterations, then the later phases; elapsed time. ``ramps`` is scheduled_ramps(scene)
    (or a level count)."""

    def __init__(self, console: Console, ramps: "list[tuple[str, int]] | int", quiet: bool):
        self.bar = Progress(TextColumn(f"{{task.description:<{RAMP_WIDTH}}}"), BarColumn(bar_width=12),
                            MofNCompleteColumn(),
                            TextColumn("{task.fields[info]}"), TimeElapsedColumn(), console=console,
                            disable=quiet, transient=False)
        self.ramps = [("loading", ramps)] if isinstance(ramps, int) else list(ramps)
        self.total, self.done, self.iterations = sum(n for _, n in self.ramps), 0, 0
        self.task = None

    def __enter__(self):
        self.bar.__enter__()
        self.task = self.bar.add_task("mesh and set-up", total=self.total, info="")
        return self

    def __exit__(self, *exc):
        return self.bar.__exit__(*exc)

    def phase(self, name: str) -> None:
        """Before the first level the phase is the description; after it the ramp stays there
        (where the test got to) and the phase takes the place of the last level's numbers."""
        if self.done == 0:
            self.bar.update(self.task, description=name)
        else:
            self.bar.update(self.task, info=f"{name} ({self.iterations} Newton iterations)")

    def level(self, level) -> None:
        self.done += 1
        self.iterations += level.iterations
        where = ramp_text(self.ramps, self.done) if self.done <= self.total else "solve: load levels"
        self.bar.update(self.task, description=where, completed=self.done, total=max(self.total, self.done),
                        info=f"t = {level.t:.4g}, Newton {level.iterations} ({self.iterations} in all)")
