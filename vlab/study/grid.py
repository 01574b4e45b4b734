"""Parameter grids from ``--set section.key=v1,v2,...`` options.

Each value is read as a TOML value (``0.3`` a float, ``2`` an integer, ``"hex"`` or bare ``hex``
a string, ``[1.2, 1.1]`` an array); commas inside brackets or quotes do not split. The grid is the
Cartesian product of all axes, in the order given (the last axis varies fastest).
"""

from __future__ import annotations

import itertools
import tomllib
from dataclasses import dataclass

from vlab.scene import SceneError, apply_overrides


@dataclass(frozen=True)
class GridPoint:
    label: dict  # the overridden keys and their values at this point
    source: dict  # the raw scene dict with the overrides applied
    base_dir: str = "."  # the scene file's folder: relative paths in ``source`` are taken from it


def _split_top_level(text: str) -> list[str]:
    parts, depth, quote, current = [], 0, None, []
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch == "[":
            depth += 1
        elif ch == "]":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append("".join(current))
            current = []
            continue
        current.append(ch)
    parts.append("".join(current))
    return [p.strip() for p in parts]


def parse_value(text: str):
    """A TOML literal, or the bare text as a string (so ``cell=hex`` works unquoted)."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_axis(option: str) -> tuple[str, list]:
    """``"material.nu=0.3,0.45"`` -> ``("material.nu", [0.3, 0.45])``; SceneError if malformed."""
    key, sep, values = option.partition("=")
    key = key.strip()
    items = _split_top_level(values) if sep else []
    if not key or not sep or not any(items) or any(not item for item in items):
        raise SceneError(f"--set {option!r}: expected section.key=value1,value2,... (no empty values)")
    return key, [parse_value(item) for item in items]


def expand_grid(source: dict, axes: list[tuple[str, list]], base_dir: str = ".") -> list[GridPoint]:
    """One GridPoint per combination; unknown sections/keys of the overrides raise SceneError here
    (unknown keys inside a section, and bad values, are left to each point's own validation)."""
    keys = [key for key, _ in axes]
    if len(set(keys)) != len(keys):
        raise SceneError(f"--set: a key is given twice ({', '.join(keys)})")
    points = []
    for values in itertools.product(*(vals for _, vals in axes)):
        label = dict(zip(keys, values))
        points.append(GridPoint(label, apply_overrides(source, label), str(base_dir)))
    return points
