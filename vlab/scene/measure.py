"""``[measure]``: the |extensometer strain| window of the E and ν fits (default [0.0005, 0.0025],
ISO 527-1), the extensometer gauge length (mm; default: the specimen's own), the fit (regression
or chord) and the readings inserted in the window (modulus_points, default 9)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.shapes import SHAPES
from vlab.scene.specimen import Specimen

__all__ = ["MeasureSpec", "parse_measure"]


@dataclass(frozen=True)
class MeasureSpec:
    modulus_window: tuple[float, float]  # |strain| window for the E and nu fits
    gauge_length: float | None  # mm; None = decided by the extensometer (half the length)
    fit: str  # "regression" | "chord"
    modulus_points: int = 9  # extra readings inserted in the modulus window (0 = none)


def parse_measure(raw: Any, specimen: Specimen) -> MeasureSpec:
    t = fields.Table("measure", raw, ("modulus_window", "gauge_length", "fit", "modulus_points"))
    field = t.field("modulus_window")
    window = (0.0005, 0.0025)
    if "modulus_window" in t.raw:
        window = fields.vector(field, t.raw["modulus_window"], 2, "[a, b]", ge=0, le=0.05)
        if not window[0] < window[1]:
            raise SceneError(f"{field} must satisfy 0 <= a < b <= 0.05, got {list(window)}")
    gauge_from = SHAPES[specimen.shape].gauge_from
    if "gauge_length" in t.raw and gauge_from is not None:  # built without it: never silently ignored
        raise SceneError(f"{t.field('gauge_length')} does not apply to specimen.shape = {specimen.shape!r}: its gauge "
                         f"is {gauge_from}")
    gauge = t.number("gauge_length", default=None, gt=0, lt=specimen.length,
                     note=" (the specimen length)")
    if gauge is not None and specimen.shape == "cruciform" and gauge > specimen.dimensions.gauge_region:
        raise SceneError(f"{t.field('gauge_length')} must be in (0, specimen.gauge_region = "
                         f"{specimen.dimensions.gauge_region:g}] mm for a cruciform (the extensometers sit in "
                         f"the gauge region), got {gauge:g}")
    return MeasureSpec(modulus_window=window, gauge_length=gauge,  # type: ignore[arg-type]
                       fit=t.choice("fit", ("regression", "chord"), default="regression"),
                       modulus_points=t.integer("modulus_points", 0, 100, default=9))
