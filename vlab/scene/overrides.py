"""Dotted-key overrides of a raw scene dict (sweeps, the CLI's ``--set``, tests)."""

from __future__ import annotations

import copy
from typing import Any, Mapping

from vlab import fields
from vlab.fields import SceneError
from vlab.scene.load import SECTIONS, TOP_KEYS

__all__ = ["apply_overrides"]


def apply_overrides(data: Mapping[str, Any], overrides: Mapping[str, object]) -> dict:
    """Return a deep copy of the raw scene dict with dotted keys set, e.g.
    ``{"material.nu": 0.45, "mesh.size": 2, "name": "run-3"}``. Unknown sections or top-level
    keys raise SceneError; unknown keys inside a section are left to :func:`parse_scene`."""
    out = copy.deepcopy(dict(data))
    for dotted, value in overrides.items():
        parts = dotted.split(".")
        head = parts[0]
        if len(parts) == 1 and head in TOP_KEYS and head not in SECTIONS:
            out[head] = copy.deepcopy(value)
        elif len(parts) == 2 and head in SECTIONS:
            table = out.setdefault(head, {})
            if not isinstance(table, dict):
                raise SceneError(f"override {dotted!r}: [{head}] is not a table")
            table[parts[1]] = copy.deepcopy(value)
        elif len(parts) == 2:
            raise SceneError(f"override {dotted!r}: unknown section [{head}] "
                             f"(allowed: {', '.join(SECTIONS)}){fields.suggest(head, SECTIONS)}")
        else:
            raise SceneError(f"override {dotted!r}: expected 'section.key' or one of "
                             f"name, description{fields.suggest(dotted, TOP_KEYS)}")
    return out
