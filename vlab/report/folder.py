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
  shared files a report put in one, vlab.report.shared) and becomes a ReportFolderError
  naming the folder and the cause (a full disk says so: free space and run again). The folder the
  report was to replace is then as it was.
- A read-only ``out`` (or a read-only folder inside it) is refused before any work, like a
  read-only parent: vlab does not replace what it cannot remove whole.
- One writer per destination at a time: the temporary sibling is made under an exclusive
  ``flock`` of the parent folder, after checking that no live vlab process (this host) has a
  temporary sibling for the same name. A second run writing the same ``out`` while the first
  writes is refused (exit 2, naming the other process); it is also refused at its start if the
  other is writing then. The folder therefore always holds one whole report, never a mixture.
- The temporary folder is checked to be the one vlab made (same inode, marker present) before the
  manifest is written and before it is renamed into place: a folder deleted (or replaced) while
  the report is written is an error saying so, never a partial report with a manifest.
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
    if target.is_dir():
        _check_writable(dest, target)


def _check_writable(dest: Destination, target: Path) -> None:
    """A folder to replace must be removable whole: it and every folder in it writable (os.access
    also answers EROFS for a read-only mount, even to root)."""
    for root, dirs, _ in os.walk(target):
        if not os.access(root, os.W_OK | os.X_OK):
            where = "" if Path(root) == target else f" (its folder {str(Path(root).relative_to(target))!r})"
            raise ReportFolderError(f"{dest.option} {str(dest.path)!r} is read-only{where}: vlab does not replace "
                                    f"a folder it cannot remove whole; make it writable or choose another folder")


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


def check_destination(out: "Path | str | Destination", own: Path | None = None) -> Destination:
    """Raise ReportFolderError unless a report may be written to ``out`` (module docstring);
    ``own``: the caller's temporary folder (not another writer)."""
    dest = destination(out)
    target = Path(os.path.abspath(dest.path))
    _check_names(dest, target)
    _check_place(dest, target)
    _check_no_other_writer(dest, target, own)
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


def other_writers(target: Path, own: Path | None = None) -> list[int]:
    """The pids of the live vlab processes (this host) writing a report to ``target`` now: their
    temporary siblings, recognised by name and marker (``own`` excepted)."""
    pids = []
    try:
        candidates = list(target.parent.iterdir())
    except OSError:
        return pids
    for path in candidates:
        m = _SIBLING.match(path.name)
        if not m or m.group(1) != "tmp" or m.group(2) != _HOST or path == own:
            continue
        pid = int(m.group(3))
        if path.name.startswith(f".{target.name}.vlab-") and (path / MARKER).is_file() \
                and (pid == os.getpid() or _pid_alive(pid)):
            pids.append(pid)
    return pids


def _check_no_other_writer(dest: Destination, target: Path, own: Path | None) -> None:
    pids = other_writers(target, own)
    if pids:
        raise ReportFolderError(f"{dest.option} {str(dest.path)!r}: another vlab process (pid {pids[0]}) is "
                                f"writing its report there now; nothing was written by this run. Run again "
                                f"when it has finished, or choose another folder")


@contextmanager
def _parent_lock(parent: Path):
    """An exclusive flock of the folder ``parent`` (its own inode: no file is made); where the file
    system or platform has no flock, no lock (the name check then still catches most races)."""
    try:
        import fcntl

        fd = os.open(parent, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except (ImportError, OSError):
        yield
        return
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
        except OSError:
            pass
        yield
    finally:
        os.close(fd)  # closing the only descriptor releases the lock


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
        check_destination(dest, own=tmp)  # again: another process may have put something there meanwhile
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


def _stage(dest: Destination, target: Path) -> tuple[Path, tuple[int, int]]:
    """Make the temporary sibling (with its marker) under the parent's lock, after checking that no
    other vlab process is writing ``target``; returns it and its (device, inode)."""
    with _parent_lock(target.parent):
        clean_orphans(target.parent)
        _check_no_other_writer(dest, target, None)
        tmp = _sibling(target, "tmp")
        tmp.mkdir()  # mode 0o777 minus the umask, like any folder the user makes
    try:
        (tmp / MARKER).write_text(json.dumps({"pid": os.getpid(), "target": str(target)}), encoding="utf-8")
        st = tmp.stat()
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return tmp, (st.st_dev, st.st_ino)


def _check_staged(dest: Destination, tmp: Path, identity: tuple[int, int], marker: bool = True) -> None:
    """The temporary folder is still the one vlab made (and, before the manifest, holds the marker)."""
    try:
        st = tmp.stat()
        same = (st.st_dev, st.st_ino) == identity and (not marker or (tmp / MARKER).is_file())
    except OSError:
        same = False
    if not same:
        raise ReportFolderError(f"{dest.option} {str(dest.path)!r}: the folder vlab was writing the report into "
                                f"({str(tmp)!r}) was removed or replaced meanwhile; nothing was written")


def _failure(dest: Destination, exc: OSError, target: Path) -> ReportFolderError:
    """The ReportFolderError of an OS error while writing: the cause, and what to do where it is known."""
    cause = exc.strerror or str(exc)
    ours = exc.filename is None or str(exc.filename).startswith(str(target.parent))  # not a vlab asset's
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        cause += f": free space on the file system of {str(dest.path)!r} and run again"
    elif exc.errno == errno.ENOENT and ours:
        cause += ": a folder was removed while vlab wrote the report"
    return ReportFolderError(f"{dest.option} {str(dest.path)!r}: cannot write the report ({cause}); "
                             f"nothing was written")


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
        tmp, identity = _stage(dest, target)
        yield tmp
        _check_staged(dest, tmp, identity)
        _write_manifest(tmp, kind)
        _check_staged(dest, tmp, identity, marker=False)
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
            raise _failure(dest, exc, target) from None
        raise
