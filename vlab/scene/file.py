"""Reading a scene file: a regular file of at most MAX_SCENE_BYTES, UTF-8, read once.

A scene is a few hundred bytes of TOML; the limit (1 MiB) is far above any real scene and far
below what could exhaust memory. Anything that is not a regular file (a device such as /dev/zero,
a FIFO, a folder) is refused before reading: a device may never end, a FIFO may block forever.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from vlab.fields import SceneError

MAX_SCENE_BYTES = 1 << 20


def check_input_file(path: Path, what: str) -> None:
    """SceneError unless ``path`` is an existing regular file, saying what it is instead
    (``what``, e.g. "data file", names the input): missing, a folder, or not a regular file (a
    device, FIFO or socket: a FIFO may block for ever and a device never end, so neither is
    opened). Nothing of the file's content is read or echoed."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise SceneError(f"{what} {str(path)!r} does not exist") from None
    except OSError as exc:
        raise SceneError(f"{what} {str(path)!r} cannot be read ({exc.strerror or exc})") from None
    if stat.S_ISDIR(info.st_mode):
        raise SceneError(f"{what} {str(path)!r} is a folder, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise SceneError(f"{what} {str(path)!r} is not a regular file (a device, FIFO or socket)")


def read_scene_file(path: Path, limit: int = MAX_SCENE_BYTES) -> str:
    """The file's text; SceneError naming the file if it is not a readable UTF-8 scene file."""
    try:
        info = os.stat(path)
        if stat.S_ISDIR(info.st_mode):
            raise SceneError(f"{path}: is a folder, not a scene file")
        if not stat.S_ISREG(info.st_mode):
            raise SceneError(f"{path}: is not a regular file (a device, FIFO or socket); give a .toml scene file")
        with open(path, "rb") as fh:
            data = fh.read(limit + 1)
    except OSError as exc:
        raise SceneError(f"{path}: cannot read scene file ({exc.strerror or exc})") from None
    if len(data) > limit:
        raise SceneError(f"{path}: scene file is larger than {limit // 1024} KiB (a scene is a small TOML "
                         f"file; is this the right file?)")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(f"{path}: scene file is not UTF-8 ({exc})") from None
