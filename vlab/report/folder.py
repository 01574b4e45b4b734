"""The one writer of report folders: every command that writes a folder (run, compare, sweep, cost,
stability) goes through :func:`report_folder`.

Rules (the instrument never destroys the user's data):
- A report folder is vlab's only when vlab made it: the last file written into it is the manifest
  ``.vlab-report.json`` listing every file and folder vlab wrote. vlab replaces such a folder as a
  whole, atomically, provided it holds nothing the manifest does not list.
- An existing non-empty folder without a manifest (or holding files the manifest does not list)
  is refused with :class:`ReportFolderError` (exit 2) naming it and what it holds; ``force``
  overwrites it, except for a folder that is, or contains, the scene file, the result cache, the
  current folder or the home folder: those are refused even with ``force``.
- The report is written into a hidden sibling ``.<name>.vlab-tmp-<host>-<pid>-<token>`` (with a
  marker file) that is renamed into place only when complete; the replaced folder is first moved
  aside to ``.<name>.vlab-old-…`` and then removed. A process killed with SIGKILL leaves such a
  sibling behind: the next write into the same parent folder removes every vlab sibling whose
  process (same host, by pid) is gone. Nothing else is ever removed.
- Folders get the permissions of a plain ``mkdir`` (0o777 minus the umask), files those of a plain
  ``open`` (0o666 minus the umask).
- Any OS error while writing (a file in the way, read-only or full file system, a name too long)
  removes the temporary folder and the parent folders it created (with the ``_assets`` folder of
  shared files a report put in one, vlab.report.shared) and becomes a ReportFolderError naming the
  folder and the cause.
"""

from __future__ import annotations

import datetime as _dt
import errno
import hashlib
import json
import os
import re
import secrets
import shutil
import socket
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

MANIFEST = ".vlab-report.json"
MARKER = ".vlab-partial"  # inside a temporary folder while it is being written
NAME_MAX = 255  # POSIX file systems (ext4, xfs, tmpfs, APFS); pathconf is asked where available
_HOST = hashlib.sha256(socket.gethostname().encode()).hexdigest()[:6]
_SIBLING = re.compile(r"^\..+\.vlab-(tmp|old)-([0-9a-f]{6})-(\d+)-[0-9a-f]{8}$")
SIBLING_ROOM = len(".") + len(".vlab-tmp-") + 6 + 1 + 10 + 1 + 8  # around the name: dot, tag, host, pid, token


class ReportFolderError(Exception):
    """The report folder cannot be written (exit 2); the message names the folder and why."""


@dataclass(frozen=True)
class Destination:
    """Where a report goes and what it must never replace."""

    path: Path
    force: bool = False  # overwrite a non-empty folder vlab did not make
    protect: tuple[Path, ...] = ()  # scene files and cache folders: never inside a replaced folder
    option: str = "--out"  # how messages name the destination


def destination(out: "Path | str | Destination") -> Destination:
    return out if isinstance(out, Destination) else Destination(Path(out))


def _name_max(folder: Path) -> int:
    try:
        return os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        return NAME_MAX


def _existing_ancestor(path: Path) -> Path:
    for candidate in [path, *path.parents]:
        if candidate.exists():
            return candidate
    return Path(path.anchor or "/")


def _within(inner: Path, outer: Path) -> bool:
    """``inner`` is ``outer`` or lies inside it (both resolved)."""
    return inner == outer or outer in inner.parents


def _check_names(dest: Destination, target: Path) -> None:
    limit = _name_max(_existing_ancestor(target.parent))
    for part in target.parts[1:]:
        room = SIBLING_ROOM if part == target.name else 0
        if len(part) + room > limit:
            raise ReportFolderError(
                f"{dest.option} {str(dest.path)!r}: the name {part[:40]!r}… is {len(part)} characters; at most "
                f"{limit - room} are allowed here (the file system allows {limit}"
                + (f", vlab needs {room} for its hidden temporary sibling)" if room else ")"))


def _check_place(dest: Destination, target: Path) -> None:
    if target.exists() and not target.is_dir():
        raise ReportFolderError(f"{dest.option} {str(dest.path)!r} is a file, not a folder; give a folder "
                                f"name (vlab never replaces a file it did not make)")
    base = _existing_ancestor(target.parent)
    if not base.is_dir():
        raise ReportFolderError(f"{dest.option} {str(dest.path)!r}: {str(base)!r} is a file, so no folder can "
                                f"be made below it")
    if not os.access(base, os.W_OK | os.X_OK):
        raise ReportFolderError(f"{dest.option} {str(dest.path)!r}: cannot write into {str(base)!r} "
                                f"(read-only or no permission)")


def _never_replaced(dest: Destination) -> list[tuple[str, Path]]:
    home = Path.home()
    named = [("the current folder", Path.cwd()), ("your home folder", home)]
    named += [(f"the {'cache' if p.is_dir() else 'scene file'} {str(p)!r}", p) for p in dest.protect if p.exists()]
    return [(what, p.resolve()) for what, p in named]


def manifest_of(folder: Path) -> dict | None:
    """The manifest of a folder vlab made, or None (absent, unreadable or not a manifest)."""
    try:
        data = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    ok = isinstance(data, dict) and isinstance(data.get("files"), list) and isinstance(data.get("folders"), list)
    return data if ok else None


def _entries(folder: Path) -> tuple[set[str], set[str]]:
    files, folders = set(), set()
    for root, dirs, names in os.walk(folder):
        rel = Path(root).relative_to(folder)
        folders.update(str(rel / d) for d in dirs)
        files.update(str(rel / n) for n in names)
    return files, folders


def _foreign(folder: Path) -> list[str]:
    """What ``folder`` holds that vlab did not write (everything, if it has no manifest)."""
    files, folders = _entries(folder)
    manifest = manifest_of(folder)
    if manifest is None:
        return sorted(files | folders)
    return sorted((files - set(manifest["files"]) - {MANIFEST}) | (folders - set(manifest["folders"])))


def check_destination(out: "Path | str | Destination") -> Destination:
    """Raise ReportFolderError unless a report may be written to ``out`` (module docstring)."""
    dest = destination(out)
    target = Path(os.path.abspath(dest.path))
    _check_names(dest, target)
    _check_place(dest, target)
    if not target.is_dir():
        return dest
    resolved = target.resolve()
    for what, path in _never_replaced(dest):
        if _within(path, resolved) or _within(resolved, path) and "cache" in what:
            where = "is" if path == resolved else "contains"
            raise ReportFolderError(f"{dest.option} {str(dest.path)!r} {where} {what}: vlab never replaces it "
                                    f"(not even with --force); choose another folder")
    foreign = _foreign(target)
    if foreign and not dest.force:
        shown = ", ".join(foreign[:5]) + (f", … ({len(foreign)} entries)" if len(foreign) > 5 else "")
        made = "was not made by vlab (no .vlab-report.json)" if manifest_of(target) is None else \
            "holds files vlab did not write"
        raise ReportFolderError(f"{dest.option} {str(dest.path)!r} {made}: {shown}; choose another folder or "
                                f"pass --force to replace it")
    return dest


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def clean_orphans(parent: Path) -> list[Path]:
    """Remove the hidden siblings left in ``parent`` by vlab processes of this host that are gone
    (recognised by name and by vlab's marker or manifest inside); returns what was removed."""
    removed = []
    try:
        candidates = list(parent.iterdir())
    except OSError:
        return removed
    for path in candidates:
        m = _SIBLING.match(path.name)
        if not m or m.group(2) != _HOST or int(m.group(3)) == os.getpid() or _pid_alive(int(m.group(3))):
            continue
        if path.is_dir() and not path.is_symlink() and ((path / MARKER).is_file() or manifest_of(path)):
            shutil.rmtree(path, ignore_errors=True)
            removed.append(path)
    return removed


def _sibling(target: Path, tag: str) -> Path:
    return target.parent / f".{target.name}.vlab-{tag}-{_HOST}-{os.getpid()}-{secrets.token_hex(4)}"


def _write_manifest(tmp: Path, kind: str) -> None:
    from vlab import __version__

    files, folders = _entries(tmp)
    files.discard(MARKER)
    data = {"vlab_report": 1, "kind": kind, "vlab_version": __version__,
            "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "files": sorted(files), "folders": sorted(folders)}
    (tmp / MANIFEST).write_text(json.dumps(data, indent=1), encoding="utf-8")
    (tmp / MARKER).unlink()


def _swap(tmp: Path, dest: Destination, target: Path, attempts: int = 5) -> None:
    """Move the finished ``tmp`` to ``target``, moving a replaceable old folder aside first."""
    for _ in range(attempts):
        check_destination(dest)  # again: another process may have put something there meanwhile
        old = None
        if target.exists():
            old = _sibling(target, "old")
            try:
                os.rename(target, old)
            except FileNotFoundError:  # a concurrent vlab moved it away first
                continue
        try:
            os.rename(tmp, target)
        except OSError as exc:
            if exc.errno not in (errno.ENOTEMPTY, errno.EEXIST):
                raise
            continue  # a concurrent vlab put its report there between our two renames
        finally:
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
        return
    raise ReportFolderError(f"{dest.option} {str(dest.path)!r}: other processes keep replacing this folder")


def _made_parents(target: Path) -> list[Path]:
    """The missing ancestors of ``target``, outermost first (made now, removed again on failure)."""
    missing = [p for p in [target.parent, *target.parent.parents] if not p.exists()]
    return missing[::-1]


def _remove_shared(made: Path) -> None:
    """The shared files (vlab.report.shared) a failed report put in a parent folder it made: all
    vlab's, since the folder did not exist before this report."""
    from vlab.report.shared import ASSETS

    assets = made / ASSETS
    if assets.is_dir() and not assets.is_symlink():
        shutil.rmtree(assets, ignore_errors=True)


@contextmanager
def report_folder(out: "Path | str | Destination", kind: str = "report"):
    """Yield an empty temporary folder; on success it becomes ``out`` (module docstring)."""
    dest = check_destination(out)
    target = Path(os.path.abspath(dest.path))
    made = _made_parents(target)
    tmp = None
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        clean_orphans(target.parent)
        tmp = _sibling(target, "tmp")
        tmp.mkdir()  # mode 0o777 minus the umask, like any folder the user makes
        (tmp / MARKER).write_text(json.dumps({"pid": os.getpid(), "target": str(target)}), encoding="utf-8")
        yield tmp
        _write_manifest(tmp, kind)
        _swap(tmp, dest, target)
    except BaseException as exc:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
        for folder in reversed(made):
            _remove_shared(folder)
            try:
                folder.rmdir()
            except OSError:
                break
        if isinstance(exc, OSError):
            raise ReportFolderError(f"{dest.option} {str(dest.path)!r}: cannot write the report "
                                    f"({exc.strerror or exc}); nothing was written") from None
        raise
