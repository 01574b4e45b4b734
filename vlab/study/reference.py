"""The reference of a cost study where no analytic solution exists: Richardson per mesh family.

Every mesh family (one element order and cell type, mesh.size swept) is extrapolated on its own,
per quantity q ∈ {E, ν, final force, final stress}, from its three finest levels on the effective
element size h_eff = (Ω / n_elements)^(1/d) of the actual meshes (vlab.study.summary.effective_size),
not on the nominal mesh.size: a structured mesher rounds element counts per segment, so the nominal
ratio between levels is not the ratio of the meshes, and an order fitted on it is wrong (on the
ISO 37-2 dumb-bell mesh.size 6 → 3 → 1.5 gives 72 → 120 → 448 hexahedra, h_eff ratios 1.19 and 1.55,
not 2 and 2). Levels whose h_eff differ by less than ``MIN_RATIO`` are the same mesh or nearly so
and are skipped (the finest one kept).

The reference of q is the valid extrapolation with the smallest correction |q* − q_finest| / |q*|,
i.e. the family that is closest to its own limit (normally the higher order): the cheapest family
must not set the reference for the more accurate ones. When no family gives a valid extrapolation,
the reference is the most resolved run (highest order, then smallest h_eff) and that run's own
error for q is unknown (None), never a zero by construction.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from vlab.study.richardson import extrapolate
from vlab.study.summary import QUANTITIES

MIN_RATIO = 1.1  # successive effective sizes closer than this are not separate levels


@dataclass(frozen=True)
class FamilyFit:
    """One family's Richardson extrapolation of one quantity."""

    family: str
    quantity: str
    h_eff: tuple[float, ...]  # the effective sizes used (mm), finest first
    values: tuple[float, ...]  # q at those sizes
    value: float | None  # q*, or the finest value when not valid
    order: float | None  # observed order p in h_eff
    valid: bool
    reason: str

    @property
    def correction(self) -> float:
        """|q* − q_finest| / |q*| (inf when not valid)."""
        if not self.valid or not self.value:
            return math.inf
        return abs(self.value - self.values[0]) / abs(self.value)

    def describe(self) -> str:
        sizes = ", ".join(f"{h:.3g}" for h in self.h_eff)
        if self.valid:
            return f"{self.family}: observed order {self.order:.2f} on h_eff = {sizes} mm"
        return f"{self.family}: {self.reason} (h_eff = {sizes} mm)"

    def as_dict(self) -> dict:
        return asdict(self) | {"correction": None if math.isinf(self.correction) else self.correction}


@dataclass(frozen=True)
class RichardsonReference:
    values: dict[str, float | None]  # per quantity
    fits: dict[str, list[FamilyFit]]  # per quantity, one per family
    chosen: dict[str, FamilyFit | None]  # the fit that set the reference (None: fallback run)
    fallback_run: dict[str, int | None]  # index of the run used as reference when no fit is valid
    notes: dict[str, str]

    @property
    def orders(self) -> dict[str, float | None]:
        return {q: (fit.order if fit else None) for q, fit in self.chosen.items()}


def effective_size(summary: dict) -> float:
    mesh = summary.get("mesh") or {}
    return float(mesh["h_eff"]) if mesh.get("h_eff") else float(summary["label"]["value"])


def family_levels(summaries: list[dict], indices: list[int]) -> list[int]:
    """The runs of one family as distinct levels, finest first (h_eff ratio ≥ MIN_RATIO)."""
    kept: list[int] = []
    for i in sorted(indices, key=lambda i: effective_size(summaries[i])):
        if not kept or effective_size(summaries[i]) >= MIN_RATIO * effective_size(summaries[kept[-1]]):
            kept.append(i)
    return kept


def fit_family(family: str, quantity: str, summaries: list[dict], levels: list[int]) -> FamilyFit:
    h = [effective_size(summaries[i]) for i in levels]
    q = [summaries[i]["measured"].get(quantity) for i in levels]
    usable = [(hh, qq) for hh, qq in zip(h, q) if qq is not None and math.isfinite(qq)][:3]
    ex = extrapolate([p[0] for p in usable], [p[1] for p in usable])
    return FamilyFit(family, quantity, tuple(p[0] for p in usable), tuple(p[1] for p in usable),
                     ex.value, ex.order, ex.valid, ex.reason)


def richardson_reference(summaries: list[dict], ok: list[bool], families: list[str]) -> RichardsonReference:
    """Per-family extrapolations and the chosen reference (module docstring)."""
    members = {f: [i for i, s in enumerate(summaries) if ok[i] and s["label"]["knob"] == f] for f in families}
    levels = {f: family_levels(summaries, idx) for f, idx in members.items() if idx}
    values, fits, chosen, fallback, notes = {}, {}, {}, {}, {}
    for q in QUANTITIES:
        fits[q] = [fit_family(f, q, summaries, lv) for f, lv in levels.items()]
        valid = [fit for fit in fits[q] if fit.valid]
        best = min(valid, key=lambda fit: fit.correction) if valid else None
        chosen[q] = best
        others = "; ".join(fit.describe() for fit in fits[q] if fit is not best)
        if best is not None:
            values[q], fallback[q] = best.value, None
            notes[q] = (f"Richardson, {best.describe()} (correction {best.correction:.2g} to its finest run)"
                        + (f"; other families: {others}" if others else ""))
        else:
            run = _most_resolved(summaries, ok, q)
            fallback[q] = run
            values[q] = None if run is None else summaries[run]["measured"].get(q)
            notes[q] = ("no valid extrapolation (" + (others or "no mesh family") + "); reference = the most "
                        "resolved run, whose own error is unknown")
    return RichardsonReference(values, fits, chosen, fallback, notes)


def _most_resolved(summaries: list[dict], ok: list[bool], quantity: str) -> int | None:
    """The finest mesh's run; without mesh-size runs (an imported mesh: one mesh for all), the
    tightest Newton tolerance's."""
    def runs(knob: str) -> list[int]:
        return [i for i, s in enumerate(summaries) if ok[i] and s["label"]["knob"].startswith(knob)
                and s["measured"].get(quantity) is not None]

    if runs("mesh size"):
        return max(runs("mesh size"), key=lambda i: (summaries[i]["mesh"]["order"], -effective_size(summaries[i])))
    tight = runs("Newton rtol")
    return min(tight, key=lambda i: summaries[i]["label"]["value"]) if tight else None
