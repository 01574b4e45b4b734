"""What the CLI prints and the checks of its file options, before any work starts.

Every message is printed verbatim: the consoles never interpret rich markup (a scene error that
says ``[material]``, a folder named ``[/x]`` or the hint ``pip install "vlab[cad]"`` must reach the
user unchanged), and the coloured labels are ``rich.text.Text`` spans, not markup strings.

Two streams, as a shell expects (``vlab run … > out.txt`` keeps the results): :data:`results`
(stdout) carries what a command found (summaries, measured constants, tables, where the report
is); :data:`console` (stderr) carries progress displays, warnings and errors.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable, Optional

import typer
from rich.console import Console
from rich.text import Text

EXIT_OK, EXIT_FAILED, EXIT_INVALID = 0, 1, 2
EXIT_UNTRUSTED = 3  # vlab fit: converged, but the card is not trustworthy (docs/fit-exit-codes.md)

console = Console(stderr=True, markup=False, highlight=False, emoji=False)  # progress, warnings, errors
results = Console(markup=False, highlight=False, emoji=False)  # stdout: what the command found


def _text(parts) -> Text:
    return Text.assemble(*(p if isinstance(p, tuple) else str(p) for p in parts))


def say(*parts) -> None:
    """Print ``parts`` verbatim on stderr (progress, notes): plain strings as they are,
    ``(text, style)`` pairs styled."""
    console.print(_text(parts), soft_wrap=True)


def show(*parts) -> None:
    """Print ``parts`` verbatim on stdout (a result), as :func:`say` does."""
    results.print(_text(parts), soft_wrap=True)


def fail(label: str, message: object, code: int = EXIT_INVALID):
    """Print ``label`` in red and ``message`` verbatim, then exit with ``code``."""
    console.print(Text.assemble((label, "red"), " ", str(message)), soft_wrap=True)
    raise typer.Exit(code)


def default_scene_path() -> Path:
    """The built-in scene that ``vlab run`` (and ``vlab.compare()``) use without a scene file."""
    from importlib import resources

    return Path(str(resources.files("vlab") / "scenes" / "default.toml"))


def report_destination(out: Path, force: bool, scene: Optional[Path] = None,
                       caches: Iterable[Path] = ()):
    """The checked destination of a report (vlab.report.folder); exit 2 naming --out if refused."""
    from vlab.report.folder import Destination, ReportFolderError, check_destination
    from vlab.study.cache import DEFAULT_CACHE

    protect = tuple(p for p in (scene, DEFAULT_CACHE, *caches) if p is not None)
    try:
        return check_destination(Destination(out, force=force, protect=protect))
    except ReportFolderError as exc:
        fail("invalid output folder", exc)


def cache_folder(path: Path) -> Path:
    """``--cache`` must be a folder (or a path where one can be made); exit 2 otherwise."""
    from vlab.study.cache import CacheError, check_cache_folder

    try:
        return check_cache_folder(path)
    except CacheError as exc:
        fail("invalid option", exc)


def scheduler_address(address: Optional[str]) -> Optional[str]:
    """``--scheduler`` must look like tcp://HOST:PORT (the connection is tried when it is needed)."""
    from vlab.study.scheduler import SchedulerError, parse_address

    if address is None:
        return None
    try:
        parse_address(address)
    except SchedulerError as exc:
        fail("invalid option", exc)
    return address


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity where the OS has one, else all)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def local_workers(workers: Optional[int], scheduler: Optional[str], default: Optional[int] = 2) -> Optional[int]:
    """The worker processes of the local Dask cluster: ``--workers`` (else ``default``) capped at
    usable_cores(), said on the console when --workers asked for more: one-thread workers beyond
    the cores only compete for them, and dozens of them on a small machine time out starting
    (Dask tracebacks, no run done). None with ``--scheduler``: an existing cluster's workers are
    its own, so ``--workers`` beside it is an error (exit 2 naming both)."""
    if scheduler is not None:
        if workers is not None:
            fail("invalid option", f"--workers {workers} and --scheduler {scheduler} exclude each other: "
                                   f"--workers starts a local Dask cluster of that many processes, --scheduler "
                                   f"uses an existing cluster with its own workers; give one of them")
        return None
    cores = usable_cores()
    if workers is None:
        return None if default is None else min(default, cores)
    if workers > cores:
        say(f"--workers {workers}: capped at {cores}, the cores this machine gives vlab (one single-thread "
            f"worker process per core; more would only compete for them)")
        return cores
    return workers
