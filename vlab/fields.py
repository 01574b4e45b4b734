"""Validation of the flat tables of a scene: ``[section]`` and ``[effects.<name>]``.

Every error is a SceneError (a ValueError) whose message names the dotted field, the allowed
range or values and the input received, e.g.
``effects.plasticity.yield_stress must be > 0 (MPa, initial yield stress), got -3``;
an unknown key lists the allowed ones and suggests the nearest. The scene parser
(vlab.scene) and the parameter parsers of the effects' laws (plasticity, Mullins, noise) share
these, so a field reads and fails the same way wherever it lives.
"""

from __future__ import annotations

import difflib
import math
from typing import Any

__all__ = ["REQUIRED", "SceneError", "Table", "bounds", "choice", "integer", "number", "show",
           "suggest", "vector"]

REQUIRED = object()  # default of a key that must be given


class SceneError(ValueError):
    """An invalid scene; the message names the dotted field, the allowed values and the input."""


def suggest(word: str, options) -> str:
    """" — did you mean 'x'?" for the option nearest to a misspelt word, or ""."""
    close = difflib.get_close_matches(word, list(options), n=1)
    return f" — did you mean {close[0]!r}?" if close else ""


SHOWN_ITEMS = 5    # the items of an array (keys of a table) an error echoes before "…"
SHOWN_CHARS = 60   # the characters of a string it echoes
SHOWN_DEPTH = 3    # nested arrays and tables shown to this depth


def _brief(v: Any, depth: int = 0) -> str:
    """repr(v), abbreviated: an error quotes enough of a value to recognise it, never a
    1000-item array, a 100 kB string or a 500-deep nesting whole."""
    if isinstance(v, list):
        if depth >= SHOWN_DEPTH:
            return "[…]"
        text = ", ".join(_brief(x, depth + 1) for x in v[:SHOWN_ITEMS])
        return "[" + text + (f", … ({len(v)} items)" if len(v) > SHOWN_ITEMS else "") + "]"
    if isinstance(v, dict):
        if depth >= SHOWN_DEPTH:
            return "{…}"
        pairs = list(v.items())[:SHOWN_ITEMS]
        text = ", ".join(f"{_brief(k, depth + 1)}: {_brief(x, depth + 1)}" for k, x in pairs)
        return "{" + text + (f", … ({len(v)} keys)" if len(v) > SHOWN_ITEMS else "") + "}"
    if isinstance(v, str) and len(v) > SHOWN_CHARS:
        return repr(v[:SHOWN_CHARS]) + f"… ({len(v)} characters)"
    return repr(v)


def show(v: Any) -> str:
    """An input value as written (abbreviated: _brief), with its TOML type where the type is the
    error."""
    kind = {bool: "boolean", str: "string", list: "array", dict: "table"}.get(type(v))
    if isinstance(v, bool):
        return f"{str(v).lower()} (boolean)"
    return f"{_brief(v)} ({kind})" if kind else f"{v:g}" if isinstance(v, (int, float)) else _brief(v)


def bounds(gt=None, ge=None, lt=None, le=None) -> str:
    """The allowed range as text, e.g. "> 0 and <= 20"."""
    ops = ((">", gt), (">=", ge), ("<", lt), ("<=", le))
    return " and ".join(f"{op} {b:g}" for op, b in ops if b is not None)


def number(field: str, v: Any, *, gt=None, ge=None, lt=None, le=None, note: str = "") -> float:
    """A finite float within the bounds; ``note`` (e.g. " (MPa)") follows the range in errors."""
    rng = bounds(gt, ge, lt, le)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise SceneError(f"{field} must be a number{' ' + rng if rng else ''}{note}, got {show(v)}")
    v = float(v)
    if not math.isfinite(v):
        raise SceneError(f"{field} must be a finite number{' ' + rng if rng else ''}{note}, got {v}")
    if ((gt is not None and not v > gt) or (ge is not None and not v >= ge)
            or (lt is not None and not v < lt) or (le is not None and not v <= le)):
        raise SceneError(f"{field} must be {rng}{note}, got {v:g}")
    return v


def integer(field: str, v: Any, lo: int, hi: int) -> int:
    """An integer in lo..hi (a float with an integral value is accepted)."""
    ok = not isinstance(v, bool) and (isinstance(v, int) or (isinstance(v, float) and v.is_integer()))
    if not ok or not lo <= v <= hi:
        raise SceneError(f"{field} must be an integer {lo}..{hi}, got {show(v)}")
    return int(v)


def choice(field: str, v: Any, options: tuple[str, ...]) -> str:
    """One of the allowed strings."""
    if v not in options or not isinstance(v, str):
        hint = suggest(v, options) if isinstance(v, str) else ""
        raise SceneError(f"{field} must be one of {', '.join(options)}; got {show(v)}{hint}")
    return v


def vector(field: str, v: Any, n: int, what: str, **bounds) -> tuple[float, ...]:
    """A list of n numbers, each within the bounds (errors name the entry, field[i])."""
    if not isinstance(v, list) or len(v) != n:
        raise SceneError(f"{field} must be a list of {n} numbers {what}, got {show(v)}")
    return tuple(number(f"{field}[{i}]", x, **bounds) for i, x in enumerate(v))


class Table:
    """One table (``section`` is its dotted name, e.g. "test" or "effects.noise"): rejects
    unknown keys on creation, then reads fields by name."""

    def __init__(self, section: str, raw: Any, allowed: tuple[str, ...]):
        if not isinstance(raw, dict):
            raise SceneError(f"[{section}] must be a table, got {show(raw)}")
        for key in raw:
            if key not in allowed:
                raise SceneError(f"unknown key {key!r} in [{section}] (allowed: "
                                 f"{', '.join(allowed)}){suggest(key, allowed)}")
        self.section, self.raw = section, raw

    def field(self, key: str) -> str:
        return f"{self.section}.{key}"

    def get(self, key: str, default: Any = REQUIRED) -> Any:
        if key not in self.raw and default is REQUIRED:
            raise SceneError(f"missing required key {self.field(key)}")
        return self.raw.get(key, default)

    def number(self, key: str, default: Any = REQUIRED, **limits) -> float:
        """The number at key (``limits``: gt, ge, lt, le, note), or ``default`` if absent."""
        if key in self.raw:
            return number(self.field(key), self.raw[key], **limits)
        if default is REQUIRED:
            rng = bounds(**{k: v for k, v in limits.items() if k != "note"})
            raise SceneError(f"missing required key {self.field(key)}: a number"
                             f"{' ' + rng if rng else ''}{limits.get('note', '')}")
        return default

    def integer(self, key: str, lo: int, hi: int, default: Any = REQUIRED) -> int:
        return integer(self.field(key), self.get(key, default), lo, hi)

    def choice(self, key: str, options: tuple[str, ...], default: Any = REQUIRED) -> str:
        return choice(self.field(key), self.get(key, default), options)
