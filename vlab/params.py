"""Validation of a flat table of effect parameters (``[effects.<name>]`` of a scene).

Every error is a ValueError whose message names the dotted field (``<prefix>.<key>``), the
allowed range and the value received, e.g.
``effects.plasticity.yield_stress must be a number > 0 (MPa), got -3``.
Unknown keys are rejected with the list of allowed keys.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["ParamTable"]

_MISSING = object()


def _show(v: Any) -> str:
    return repr(v) if isinstance(v, str) else str(v)


class ParamTable:
    """One parameter table: rejects unknown keys on creation, then reads fields by name."""

    def __init__(self, raw: Any, prefix: str, allowed: tuple[str, ...]):
        if not isinstance(raw, dict):
            raise ValueError(f"[{prefix}] must be a table of parameters, got {_show(raw)}")
        for key in raw:
            if key not in allowed:
                raise ValueError(f"unknown key {key!r} in [{prefix}] (allowed: {', '.join(allowed)})")
        self.raw, self.prefix = raw, prefix

    def field(self, key: str) -> str:
        return f"{self.prefix}.{key}"

    def number(self, key: str, default: Any = _MISSING, *, gt: float | None = None,
               ge: float | None = None, lt: float | None = None, unit: str = "") -> float:
        """A finite float with the given bounds; ``default`` when the key is absent."""
        rng = " and ".join(s for s in (
            f"> {gt:g}" if gt is not None else "", f">= {ge:g}" if ge is not None else "",
            f"< {lt:g}" if lt is not None else "") if s)
        what = f"a number{' ' + rng if rng else ''}{f' ({unit})' if unit else ''}"
        if key not in self.raw:
            if default is _MISSING:
                raise ValueError(f"missing required key {self.field(key)}: {what}")
            return default
        v = self.raw[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ValueError(f"{self.field(key)} must be {what}, got {_show(v)}")
        if ((gt is not None and not v > gt) or (ge is not None and not v >= ge)
                or (lt is not None and not v < lt)):
            raise ValueError(f"{self.field(key)} must be {what}, got {v:g}")
        return float(v)

    def integer(self, key: str, default: Any, lo: int, hi: int) -> int:
        """An integer in [lo, hi] (a float with an integral value is accepted)."""
        v = self.raw.get(key, default)
        ok = not isinstance(v, bool) and (isinstance(v, int) or (isinstance(v, float) and v.is_integer()))
        if not ok or not lo <= v <= hi:
            raise ValueError(f"{self.field(key)} must be an integer {lo}..{hi}, got {_show(v)}")
        return int(v)
