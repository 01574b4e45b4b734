"""Reading vlab's input files: a regular file of bounded size, UTF-8, read once; TOML parsed to a
bounded depth. Scenes, fit files and their data CSVs all read through here, so each refuses a
folder, a device, a binary file or a pathological TOML with the same message naming the file.

A scene is a few hundred bytes of TOML; the limit (1 MiB) is far above any real scene and far
below what could exhaust memory. A data CSV may be a long machine record (MAX_DATA_BYTES).
Anything that is not a regular file (a device such as /dev/zero, a FIFO, a folder) is refused
before reading: a device may never end, a FIFO may block forever.

TOML depth: Python's tomllib parses nested arrays and inline tables recursively, so
``a = [[[[…]]]]`` a few hundred levels deep (200 kB, under the size limit) raises RecursionError
inside the parser. No vlab file nests deeper than a few levels (``[effects.viscoelastic]``, a
list of lists); MAX_TOML_DEPTH is far above that and far below the interpreter's stack.
"""

from __future__ import annotations

import os
import stat
import tomllib
from pathlib import Path

from vlab.fields import SceneError

__all__ = ["MAX_SCENE_BYTES", "MAX_DATA_BYTES", "MAX_TOML_DEPTH", "read_text_file", "read_scene_file",
           "parse_toml"]

MAX_SCENE_BYTES = 1 << 20
MAX_DATA_BYTES = 64 << 20
MAX_TOML_DEPTH = 32


def read_text_file(path: Path, what: str, limit: int = MAX_SCENE_BYTES, encoding: str = "utf-8") -> str:
    """The text of ``path`` (``what``: "scene file", "fit file", "data file", for messages);
    SceneError naming the file if it is missing, not a regular file, over ``limit`` bytes or not
    UTF-8 (``encoding`` "utf-8-sig" also drops a byte-order mark)."""
    try:
        info = os.stat(path)
        if stat.S_ISDIR(info.st_mode):
            raise SceneError(f"{what} {str(path)!r} is a folder, not a file")
        if not stat.S_ISREG(info.st_mode):
            raise SceneError(f"{what} {str(path)!r} is not a regular file (a device, FIFO or socket: never "
                             "opened, as it may block or never end)")
        with open(path, "rb") as fh:
            data = fh.read(limit + 1)
    except FileNotFoundError:
        raise SceneError(f"{path}: cannot read {what} (it does not exist)") from None
    except OSError as exc:
        raise SceneError(f"{path}: cannot read {what} ({exc.strerror or exc})") from None
    if len(data) > limit:
        raise SceneError(f"{path}: {what} is larger than {limit // 1024} KiB (is this the right file?)")
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise SceneError(f"{path}: {what} is not UTF-8 text (byte 0x{data[exc.start]:02x} at offset "
                         f"{exc.start}; a binary file, or text saved in another encoding: save it as "
                         f"UTF-8)") from None


def read_scene_file(path: Path, limit: int = MAX_SCENE_BYTES) -> str:
    """The scene file's text; SceneError naming the file if it is not a readable UTF-8 scene file."""
    return read_text_file(path, "scene file", limit)


def parse_toml(text: str, origin: str, what: str = "file") -> dict:
    """The TOML document ``text`` (read from ``origin``); SceneError naming it on a syntax error
    or a nesting deeper than MAX_TOML_DEPTH (checked without recursion)."""
    too_deep = SceneError(f"{origin}: the {what} nests arrays or tables more than {MAX_TOML_DEPTH} levels "
                          "deep (a vlab file needs a few): is this the right file?")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{origin}: TOML syntax error: {exc}") from None
    except RecursionError:
        raise too_deep from None
    stack = [(data, 1)]
    while stack:
        value, depth = stack.pop()
        if depth > MAX_TOML_DEPTH:
            raise too_deep
        children = value.values() if isinstance(value, dict) else value
        stack.extend((v, depth + 1) for v in children if isinstance(v, (dict, list)))
    return data
