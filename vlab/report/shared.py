"""Files the reports of one folder share: ``<reports root>/_assets/`` beside the report folders
(``reports/_assets/plotly-<version>.min.js``: one 4.8 MB copy of plotly.js for every report in
``reports/`` instead of one per report), referenced relatively (``../_assets/…``), so the reports
open offline and a report folder moves together with its ``_assets`` folder.

The error contract of vlab.report.folder holds here too: vlab never replaces a file it did not
make. A shared file is written only where none of its name exists, through a hidden temporary file
hard-linked into place (``os.link`` refuses an existing name, so a file put there meanwhile is never
replaced); a file of that name is used only when its bytes are vlab's. The name carries the
library's version, so an upgrade adds a file and never needs to replace the one older reports use.
Sharing never fails a report: where the file cannot be shared (a foreign file of that name, a
read-only folder, a file called ``_assets``), :func:`share` returns None and the caller ships its
own copy in the report folder, as before.
"""

from __future__ import annotations

import filecmp
import os
import secrets
import shutil
from pathlib import Path

ASSETS = "_assets"


def share(src: Path, root: Path, name: str) -> str | None:
    """``src`` as ``root/_assets/name`` (made if absent, used if identical); the path relative to
    a report folder in ``root`` (``../_assets/name``), or None where it cannot be shared."""
    folder, dest = root / ASSETS, root / ASSETS / name
    try:
        if not (dest.exists() or dest.is_symlink()):
            folder.mkdir(exist_ok=True)  # mode 0o777 minus the umask, like any folder the user makes
            _place(src, dest)
        ok = dest.is_file() and not dest.is_symlink() and filecmp.cmp(dest, src, shallow=False)
    except OSError:
        return None
    return f"../{ASSETS}/{name}" if ok else None


def _place(src: Path, dest: Path) -> None:
    """Copy ``src`` to ``dest`` unless a file of that name exists by then (never replaced): a
    complete hidden copy linked into place, or an exclusive create where links are not allowed."""
    tmp = dest.parent / f".{dest.name}.vlab-tmp-{os.getpid()}-{secrets.token_hex(4)}"
    try:
        shutil.copyfile(src, tmp)
        try:
            os.link(tmp, dest)
        except FileExistsError:
            return  # another vlab (or the user) was first: its file is compared by the caller
        except OSError:  # a file system without hard links (FAT, some network shares)
            _exclusive_copy(src, dest)
    finally:
        tmp.unlink(missing_ok=True)


def _exclusive_copy(src: Path, dest: Path) -> None:
    try:
        with open(dest, "xb") as out, open(src, "rb") as data:
            try:
                shutil.copyfileobj(data, out)
            except BaseException:
                out.close()
                dest.unlink(missing_ok=True)  # our own partial file, made by the "x" open above
                raise
    except FileExistsError:
        return
