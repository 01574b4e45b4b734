"""The registry of solver formats a material card can be exported to and read back from.

Contract. An ``Exporter`` entry says, for the name given to ``vlab export --to``:

- ``default_file``: the file written when no ``--out`` is given (``abaqus.inp``, ...);
- ``comment``: the target's comment prefix, for the header (every written file starts with the
  header of vlab.export.header: units, convention, source, Drucker-stable range);
- ``models``: ``{vlab model: Mapping}``, one entry per model the target has *exactly*
  (``Mapping``: the target's keyword, the volumetric energy U(J) it uses — a name of
  vlab.materials.volumetric, or None for a coupled law with no separate U — the largest number
  of Ogden terms it allows, and the manual section it follows). A model or volumetric form not
  listed is refused by ``refusal`` (exit 2, no file), naming the targets that have it;
- ``write(card, units) -> str``: the file text of a validated ``ExportCard`` (vlab.export.card)
  in the target's convention, constants with at least 12 significant digits, in ``units``
  (vlab.export.header.Units);
- ``read(text, where, units) -> ExportCard``: the inverse (``vlab import-card``; ``units`` as for
  ``write``, from the file's vlab header or ``--units``); malformed input raises
  ``CardFormatError`` naming ``where`` and the line;
- ``parts``: the card parts the target writes: ``"hyperelastic"`` always; ``"viscoelastic"``
  (Prony) and ``"mullins"`` (Ogden–Roxburgh) where the target's part is vlab's model, written and
  read back by its ``write``/``read`` (the card's constants in ``card.effects``). A card carrying
  a part a target does not list is refused by ``refusal``, never written without it;
- ``check_parts(card) -> str | None``: why the target's part is not vlab's model for this card
  (vlab.export.parts.needs: the ground law, J = 1, the number of terms), or None.

A card may be written in another of vlab's forms that is the same model (vlab.export.card.forms:
an incompressible neo-hookean fit as the split neo-Hooke); ``form_for`` gives the one written.

Adding a target is one file in vlab/export/ with its writer, reader and convention (the manual
section in its docstring), one ``register`` call in vlab/export/__init__.py, and its oracle in
tests/test_export_oracles.py (the target's strain energy coded from its manual).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

__all__ = ["Mapping", "Exporter", "EXPORTERS", "register", "refusal", "supporting", "form_for", "CardFormatError"]


class CardFormatError(ValueError):
    """A card file that cannot be read: the message names the file and line."""


@dataclass(frozen=True)
class Mapping:
    keyword: str                 # the target's card keyword / type
    volumetric: str | None       # the target's U(J) (vlab.materials.volumetric name) or None (coupled law)
    manual: str                  # the manual section the mapping follows
    max_terms: int | None = None  # Ogden: the largest N the target allows


@dataclass(frozen=True)
class Exporter:
    name: str
    default_file: str
    comment: str
    models: dict[str, Mapping]
    write: Callable
    read: Callable
    parts: tuple[str, ...] = ("hyperelastic",)
    doc: str = ""
    notes: dict[str, str] = field(default_factory=dict)  # model -> why the target is refused
    check_parts: Callable | None = None


EXPORTERS: dict[str, Exporter] = {}


def register(exporter: Exporter) -> Exporter:
    EXPORTERS[exporter.name] = exporter
    return exporter


def _reason(exporter: Exporter, card) -> str | None:
    """Why ``exporter`` cannot write ``card`` in any of its forms exactly, or None."""
    from vlab.export.card import forms

    reasons = [_reason_one(exporter, c) for c in forms(card)]
    return None if None in reasons else reasons[-1]


def form_for(name: str, card):
    """The form of ``card`` target ``name`` writes (vlab.export.card.forms), or None."""
    from vlab.export.card import forms

    return next((c for c in forms(card) if _reason_one(EXPORTERS[name], c) is None), None)


def _reason_one(exporter: Exporter, card) -> str | None:
    extra = [p for p in card.parts if p not in exporter.parts]
    if extra:
        return f"{exporter.name} has no {' or '.join(extra)} part that is vlab's model"
    m = exporter.models.get(card.model)
    if m is None:
        note = exporter.notes.get(card.model, "")
        return f"{exporter.name} has no {card.model} card with vlab's energy" + (f" ({note})" if note else "")
    n = card.terms
    if m.max_terms is not None and n > m.max_terms:
        return f"{exporter.name}'s {m.keyword} allows at most {m.max_terms} terms, the card has {n}"
    if m.volumetric is not None and card.volumetric != m.volumetric and not card.stand_in:
        from vlab.materials.volumetric import VOLUMETRIC

        if m.volumetric not in VOLUMETRIC:  # a U(J) vlab does not have: only an incompressible fit's stand-in K
            return (f"{exporter.name}'s {m.keyword} has U(J) = {m.volumetric}, which is none of vlab's; only an "
                    "incompressible fit (whose K is a stand-in) is written to it")
        return (f"{exporter.name}'s {m.keyword} has U(J) = {VOLUMETRIC[m.volumetric].formula}, the card's "
                f"volumetric is {card.volumetric!r} ({VOLUMETRIC[card.volumetric].formula}); "
                f"set material.volumetric = {m.volumetric!r} to export it")
    if exporter.check_parts is not None:
        return exporter.check_parts(card)
    return None


def supporting(card) -> list[str]:
    """The targets that write ``card`` exactly."""
    return [name for name, e in EXPORTERS.items() if _reason(e, card) is None]


def refusal(name: str, card) -> str | None:
    """None if target ``name`` writes ``card`` exactly; else the message of the refusal,
    naming the targets that do."""
    reason = _reason(EXPORTERS[name], card)
    if reason is None:
        return None
    others = supporting(card)
    where = (f"targets that write it exactly: {', '.join(others)}" if others
             else "no target writes this card exactly")
    return f"cannot export the {card.describe()} to {name}: {reason}; {where}"
