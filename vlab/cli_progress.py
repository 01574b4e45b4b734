"""What the terminal shows while a command works: one live rich display (phase, load level,
Newton iterations, elapsed time) instead of a line per level, and warnings printed once each.
The library never prints; only the CLI builds these."""

from __future__ import annotations

import logging

from rich.console import Console
from rich.logging import RichHandler
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn


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
    from vlab.loading.kinds import kind_of
    from vlab.loading.protocol import protocol_levels

    m, test = scene.measure, scene.test
    grip_stretch = tuple(1.0 + g for g in kind_of(test).grip_strain(test.targets))
    return len(protocol_levels(test.protocol, grip_stretch, test.steps, m.modulus_window, m.modulus_points))


class RunProgress:
    """The live display of one `vlab run`: phase, levels done of scheduled, the last level's load
    factor t and Newton iterations, elapsed time."""

    def __init__(self, console: Console, total: int, quiet: bool):
        self.bar = Progress(TextColumn("{task.description:<28}"), BarColumn(), MofNCompleteColumn(),
                            TextColumn("{task.fields[info]}"), TimeElapsedColumn(), console=console,
                            disable=quiet, transient=False)
        self.total, self.done, self.iterations = total, 0, 0
        self.task = None

    def __enter__(self):
        self.bar.__enter__()
        self.task = self.bar.add_task("mesh and set-up", total=self.total, info="")
        return self

    def __exit__(self, *exc):
        return self.bar.__exit__(*exc)

    def phase(self, name: str) -> None:
        self.bar.update(self.task, description=name)

    def level(self, level) -> None:
        self.done += 1
        self.iterations += level.iterations
        self.bar.update(self.task, description="solve: load levels", completed=self.done,
                        total=max(self.total, self.done),
                        info=f"t = {level.t:.4g}, Newton {level.iterations} ({self.iterations} in all)")
