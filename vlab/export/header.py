"""What every exported card says about itself, and how its numbers are written.

``Units``: vlab's system (N, mm, MPa, s, t/mm³) or ``--units SI`` (N, m, Pa, s, kg/m³): stresses
and moduli scale by 1 or 1e6, D = 2/K by the inverse, density (t/mm³) by 1 or 1e12; stretches,
exponents and ν are dimensionless. ``num`` writes a float with 17 significant digits (exact
round trip of a double). ``header`` is the comment block on top of every card: the vlab card it
came from, the target's convention in one line, the units, the source (fit name, data ranges,
vlab version, date), the bulk term (a stand-in K says so) and the Drucker-stable stretch range
per mode when the source is a fit.
"""

from __future__ import annotations

import datetime
from dataclasses import dataclass

__all__ = ["Units", "UNITS", "num", "header", "units_of_header"]


@dataclass(frozen=True)
class Units:
    name: str
    stress: float    # MPa -> the file's stress unit
    density: float   # t/mm³ -> the file's density unit
    line: str


UNITS = {
    "mm": Units("mm", 1.0, 1.0, "N, mm, MPa, s, t/mm³ (vlab's units)"),
    "SI": Units("SI", 1e6, 1e12, "N, m, Pa, s, kg/m³ (SI)"),
}


def num(v: float) -> str:
    """17 significant digits, exponent form (every target reads it)."""
    return f"{float(v):.16e}"


def units_of_header(text: str, default: str = "mm") -> str:
    """The units a vlab header names (``units: ...``), else ``default``."""
    for line in text.splitlines()[:40]:
        if "units: " in line:
            return "SI" if "(SI)" in line else "mm"
    return default


def _stability(stability: dict) -> list[str]:
    out = []
    for kind, s in stability.items():
        parts = []
        for side, bound, lim in (("tension", "up to", 10.0), ("compression", "down to", 0.1)):
            x = s.get(side)
            if x is None:
                continue
            stop = x.get("unstable_from") or x.get("locks_at")
            what = "unstable from" if x.get("unstable_from") else "locks at" if x.get("locks_at") else "stable"
            parts.append(f"{side} {what} λ = {stop:.6g}" if stop else f"{side} stable {bound} λ = {lim:g}")
        out.append(f"  {kind}: " + "; ".join(parts))
    return out


def _source_lines(card) -> list[str]:
    from vlab import __version__

    src = card.source
    date = datetime.date.today().isoformat()
    if src is None:
        return [f"source: vlab {__version__}, {date}"]
    what = f"fit {src.name!r} ({src.path})" if src.kind == "fit" else f"{src.kind} {src.path}"
    lines = [f"source: {what}; vlab {__version__}, {date}"]
    for name, kind, role, lo, hi in src.ranges:
        lines.append(f"  data {name} ({kind}, {role}): stretch {lo:.6g} … {hi:.6g}")
    if src.stability:
        lines.append("Drucker-stable stretch range of the fitted card (vlab.identify.drucker, scanned 0.1 … 10):")
        lines += _stability(src.stability)
    return lines


def _bulk_line(card, units: Units, target_u: str | None) -> list[str]:
    if card.K is None:
        return []
    K = card.K * units.stress
    if card.stand_in:
        r = card.K / card.mu0
        return [f"bulk: K = {K:.12g} is an incompressible fit's stand-in (K = {r:.6g} μ0): the fit determines "
                f"only the isochoric energy; written with U(J) = {target_u or 'the target own'} "
                "(use a hybrid / mixed formulation)"]
    return [f"bulk: K = {K:.12g}, U(J) = {target_u}"]


def header(card, target: str, keyword: str, convention: str, units: Units, manual: str,
           target_u: str | None = None, parts: tuple[str, ...] = ()) -> list[str]:
    """The header lines (without comment prefix); ``parts``: the target's convention and manual
    section for each viscoelastic / Mullins part it writes (after vlab's own, in its names)."""
    from vlab.export.parts import prony_lines

    lines = [f"vlab material card: {card.describe()} -> {target} {keyword}",
             f"convention: {convention}",
             f"follows: {manual}"]
    if card.form:
        lines.append(f"form: {card.form}")
    lines += prony_lines(card) + list(parts)
    lines.append(f"units: {units.line}")
    lines += _bulk_line(card, units, target_u)
    lines += _source_lines(card)
    if card.source is not None and card.source.note and card.source.kind != "fit":
        lines.append(f"note: {card.source.note}")
    return lines


def commented(lines: list[str], prefix: str) -> str:
    return "".join(f"{prefix} {line}".rstrip() + "\n" for line in lines)
