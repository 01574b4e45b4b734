"""Dimensions of standard dogbones, shipped as package data (``vlab/data/standards/*.toml``).

Each file holds the keys of :data:`vlab.geometry.dogbone.DIMENSION_KEYS` plus ``standard``, the
name a scene uses (``[specimen] standard = "ISO 527-2 1A"``). Names match case- and
space-insensitively.
"""

from __future__ import annotations

import tomllib
from functools import lru_cache
from importlib import resources


def _key(name: str) -> str:
    return "".join(name.lower().split())


@lru_cache(maxsize=1)
def standard_table() -> dict[str, dict]:
    """Canonical name -> dimension dict, read from the package data."""
    table = {}
    folder = resources.files("vlab") / "data" / "standards"
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            data = tomllib.loads(entry.read_text(encoding="utf-8"))
            table[data["standard"]] = data
    return table


def standard_names() -> tuple[str, ...]:
    return tuple(standard_table())


def standard_dimensions(name: str) -> dict | None:
    """The dimensions of a named standard specimen (a copy), or None if unknown."""
    for canonical, data in standard_table().items():
        if _key(canonical) == _key(name):
            return dict(data)
    return None
