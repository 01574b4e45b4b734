"""Content-addressed cache of run summaries: one JSON file per (scene, vlab version, knobs).

key = sha256 of the canonical JSON {"scene": Scene.content_hash(), "vlab": version, "knobs": knobs}
(sorted keys), where ``knobs`` are whatever beyond the scene changes the summary (e.g. whether the
report was timed). A file appears only complete: it is written to a temporary sibling and
``os.replace``d into place (atomic on POSIX), so a sweep killed at any moment leaves either a
finished entry or none, and a rerun computes exactly the missing ones.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import tempfile
from pathlib import Path

from vlab import __version__

log = logging.getLogger(__name__)

DEFAULT_CACHE = Path("reports") / ".cache"


def cache_key(scene_hash: str, knobs: dict | None = None, version: str = __version__) -> str:
    text = json.dumps({"scene": scene_hash, "vlab": version, "knobs": knobs or {}},
                      sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


class SummaryCache:
    """Summaries stored as ``<folder>/<key[:2]>/<key>.json``."""

    def __init__(self, folder: Path | str = DEFAULT_CACHE):
        self.folder = Path(folder)

    def path(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.json"

    def get(self, key: str) -> dict | None:
        """The stored summary, or None if absent or unreadable (then it is recomputed)."""
        path = self.path(key)
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            log.warning("ignoring unreadable cache entry %s (%s)", path, exc)
            return None

    def put(self, key: str, summary: dict) -> Path:
        path = self.path(key)
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{key[:12]}.", suffix=".tmp", dir=path.parent)
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                json.dump(summary, fh, indent=1, sort_keys=True)
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
        return path

    def __len__(self) -> int:
        return sum(1 for _ in self.folder.glob("*/*.json")) if self.folder.exists() else 0
