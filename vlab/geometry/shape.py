"""One entry of the specimen-shape registry (the contract: vlab/geometry/shapes.py)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

__all__ = ["Shape"]


@dataclass(frozen=True)
class Shape:
    name: str
    keys: tuple[str, ...]
    parse: Callable[..., Any]
    build: Callable[..., Any]
    tests: dict[str, tuple[str, ...]]
    symmetric: bool = False
    gauge_size: bool = False
    thickness: Callable[[Any], float] | None = None
    count: Callable[[Any, Any], Any] | None = None  # (spec, mesh) -> counts.MeshCount, for the size budget
    doc: str = ""
    # None: ``build`` places the extensometer over measure.gauge_length; else where the shape's gauge
    # marks come from instead, named in the error that refuses measure.gauge_length
    gauge_from: str | None = None
