"""Content-addressed cache of run summaries: one JSON file per set of inputs.

key = sha256 of the canonical JSON (sorted keys) of
    {"scene": Scene.content_hash(), "files": {"specimen.file": sha256 of its bytes}, "vlab": version,
     "code": code_fingerprint(), "knobs": knobs}
i.e. everything that can change a number: the scene's content, the bytes of every file it
references (an imported mesh: a changed mesh is a new key even if the scene text is the same;
a missing file is keyed "missing"), vlab's version, the code itself (the version number is
changed by hand and lags behind the source: a summary written by other code — a field added,
a measurement changed — must not be served, so the bytes of every module and package-data file
of vlab are hashed too) and the knobs beyond the scene (e.g. whether the report was timed).

An entry stores the key it was written under and a sha256 checksum of its own content. An entry
is served only if it is a JSON object whose checksum and key match, whose vlab version is this
one, whose status is one of ok/failed/invalid and whose numbers are all finite; anything else
(edited by hand, truncated, NaN, ``[]``, ``{}``, a folder in its place) is discarded with a warning
and recomputed. A file appears only complete: it is written to a temporary sibling and
``os.replace``d into place (atomic on POSIX), so a sweep killed at any moment leaves either a
finished entry or none, and a rerun computes exactly the missing ones. The cache is an
optimisation: an entry that cannot be written (read-only folder, full disk, a folder in the way)
is a warning, never a failed study.
"""

from __future__ import annotations

import functools
import hashlib
import json
import logging
import math
import os
import tempfile
from pathlib import Path

from vlab import __version__

log = logging.getLogger(__name__)

DEFAULT_CACHE = Path("reports") / ".cache"
STATUSES = ("ok", "failed", "invalid")
_STORED = ("cache_key", "checksum")


class CacheError(ValueError):
    """The --cache option cannot be used as a cache folder (exit 2)."""


def check_cache_folder(path: Path, name: str = "--cache") -> Path:
    """``path`` if it is a folder or one can be made there; CacheError naming ``name`` (the option
    or key that gave it: --cache, fe.cache) otherwise."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise CacheError(f"{name} {str(path)!r} is a file, not a folder (the cache is a folder of run summaries)")
    base = next((p for p in [path, *path.parents] if p.exists()), Path("/"))
    if not base.is_dir():
        raise CacheError(f"{name} {str(path)!r}: {str(base)!r} is a file, so no folder can be made below it")
    return path


def file_digest(path: Path) -> str:
    """sha256 of the file's bytes, or "missing" if it cannot be read."""
    digest = hashlib.sha256()
    try:
        with open(path, "rb") as fh:
            for block in iter(lambda: fh.read(1 << 20), b""):
                digest.update(block)
    except OSError:
        return "missing"
    return digest.hexdigest()


def referenced_files(source: dict, base_dir: str | Path = ".") -> dict[str, Path]:
    """The files a raw scene dict references, by field (today: specimen.file), resolved against
    ``base_dir`` (the scene file's folder) like the scene parser does."""
    specimen = source.get("specimen") if isinstance(source, dict) else None
    name = specimen.get("file") if isinstance(specimen, dict) else None
    if not isinstance(name, str) or not name:
        return {}
    path = Path(name)
    return {"specimen.file": path if path.is_absolute() else Path(base_dir) / path}


def fingerprint(root: Path) -> str:
    """sha256 over the source and package data under ``root``: relative path and bytes of every
    *.py and *.toml in sorted order (bytecode and other files do not count)."""
    digest = hashlib.sha256()
    for path in sorted(p for ext in ("*.py", "*.toml") for p in root.rglob(ext) if "__pycache__" not in p.parts):
        digest.update(path.relative_to(root).as_posix().encode("utf-8") + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


@functools.lru_cache(maxsize=1)
def code_fingerprint() -> str:
    """fingerprint() of vlab's own package, once per process (~300 files, ~30 ms)."""
    return fingerprint(Path(__file__).resolve().parents[1])


def cache_key(scene_hash: str, knobs: dict | None = None, version: str = __version__,
              files: dict[str, str] | None = None, code: str | None = None) -> str:
    """sha256 of every input that can change a number (module docstring); ``code`` defaults to
    this process's code_fingerprint()."""
    text = json.dumps({"scene": scene_hash, "files": files or {}, "vlab": version,
                       "code": code_fingerprint() if code is None else code, "knobs": knobs or {}},
                      sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _checksum(entry: dict) -> str:
    body = {k: v for k, v in entry.items() if k != "checksum"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":"),
                                     default=str).encode("utf-8")).hexdigest()


def _finite(value) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, dict):
        return all(_finite(v) for v in value.values())
    if isinstance(value, list):
        return all(_finite(v) for v in value)
    return True


def entry_problem(entry, key: str) -> str | None:
    """Why ``entry`` must not be served for ``key`` (None: it may)."""
    if not isinstance(entry, dict) or not entry:
        return f"not a summary ({type(entry).__name__})"
    if entry.get("cache_key") != key:
        return "it claims another key"
    if entry.get("checksum") != _checksum(entry):
        return "its checksum does not match its content (edited or corrupted)"
    if entry.get("vlab_version") != __version__:
        return f"written by vlab {entry.get('vlab_version')!r}"
    if entry.get("status") not in STATUSES or not isinstance(entry.get("label", {}), dict):
        return f"status {entry.get('status')!r} is not one of {', '.join(STATUSES)}"
    if not _finite(entry):
        return "it holds a non-finite number"
    return None


class SummaryCache:
    """Summaries stored as ``<folder>/<key[:2]>/<key>.json``."""

    def __init__(self, folder: Path | str = DEFAULT_CACHE):
        self.folder = Path(folder)

    def path(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.json"

    def get(self, key: str) -> dict | None:
        """The stored summary, or None if absent or not valid (then it is recomputed)."""
        path = self.path(key)
        try:
            entry = json.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            log.warning("discarding unreadable cache entry %s (%s)", path, exc)
            return None
        problem = entry_problem(entry, key)
        if problem:
            log.warning("discarding cache entry %s: %s", path, problem)
            return None
        return {k: v for k, v in entry.items() if k not in _STORED}

    def put(self, key: str, summary: dict) -> Path | None:
        """Store ``summary`` under ``key``; None (and a warning) if it cannot be written."""
        path = self.path(key)
        entry = dict(summary) | {"cache_key": key}
        entry["checksum"] = _checksum(entry)
        if path.is_dir() or path.is_symlink():
            log.warning("not caching %s: something that is not a cache entry is in its place", path)
            return None
        tmp = None
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{key[:12]}.", suffix=".tmp", dir=path.parent)
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                json.dump(entry, fh, indent=1, sort_keys=True)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, path)
        except BaseException as exc:
            if tmp is not None:
                Path(tmp).unlink(missing_ok=True)
            if not isinstance(exc, OSError):
                raise
            log.warning("not caching %s (%s)", path, exc.strerror or exc)
            return None
        return path

    def __len__(self) -> int:
        return sum(1 for _ in self.folder.glob("*/*.json")) if self.folder.exists() else 0
