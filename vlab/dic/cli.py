"""The body of ``vlab dic`` (registered in vlab/cli.py): check, correlate, write, print."""

from __future__ import annotations

import time
from pathlib import Path

from vlab.cli_io import EXIT_INVALID, fail, say, show


def run_dic(reference: Path, deformed: list[Path], options: dict, dest, quiet: bool) -> None:
    """Exit 2 naming the file or option for a bad input (nothing written); else write the folder."""
    from vlab.dic.command import DICError, ImageError, Settings, analyse, write
    from vlab.report.folder import ReportFolderError

    settings = Settings(**options)
    try:
        settings.check()
    except DICError as exc:
        flag = "--" + exc.setting.replace("_", "-")
        fail("invalid option", f"{flag}{str(exc)[len(exc.setting):]}", EXIT_INVALID)

    def progress(stem, field, seconds):
        if not quiet:
            failed = ", ".join(f"{n} {name}" for name, n in field.counts().items() if n and name != "ok")
            say(f"  {stem}: {field.converged:.1%} of {field.status.size} subsets converged ({seconds:.2f} s)"
                + (f"; failed: {failed}" if failed else ""))

    start = time.perf_counter()
    try:
        fields, depths = analyse(reference, deformed, settings, progress)
    except ImageError as exc:
        fail("invalid image", exc)
    except DICError as exc:
        fail("invalid input", exc)
    mixed = [stem for stem in depths if depths[stem] != depths[str(reference)]]
    if mixed and not quiet:
        say(f"  note: {', '.join(f'{s} is {depths[s]}' for s in mixed)}, the reference {depths[str(reference)]}: "
            f"ZNSSD ignores a grey-level scale, so they correlate; fewer grey levels add noise")
    try:
        write(dest, reference, fields, settings, time.perf_counter() - start, depths)
    except ReportFolderError as exc:
        fail("invalid output folder", exc)
    show(f"report: {dest.path / 'index.html'}")
