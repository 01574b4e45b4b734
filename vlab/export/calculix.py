"""CalculiX ``*HYPERELASTIC`` (CalculiX CrunchiX User's Manual: "*HYPERELASTIC" in the input
deck format chapter and "Hyperelastic materials" in the theory chapter).

CalculiX takes Abaqus' keyword with Abaqus' strain energies and data lines (vlab.export.abaqus):
ARRUDA-BOYCE (μ, λm, D; U_vol = (1/D)((J² − 1)/2 − ln J)), MOONEY-RIVLIN (C10, C01, D1),
NEO HOOKE (C10, D1), OGDEN for N = 1, 2, 3 only (μ1, α1, …, D1, …, DN; U_vol = Σ (J − 1)^(2i)/Di),
POLYNOMIAL / REDUCED POLYNOMIAL for N = 1, 2, 3 (Ci0, Di) and YEOH (C10, C20, C30, D1, D2, D3);
an optional last entry of a data line is the temperature (vlab writes none). So the written file
is Abaqus' card with the Ogden limit N ≤ 3; Gent and vlab's coupled neo-hookean are refused as
in Abaqus.
"""

from __future__ import annotations

from vlab.export import abaqus
from vlab.export.registry import Exporter, Mapping

__all__ = ["CALCULIX"]

_MANUAL = "CalculiX CrunchiX User's Manual, *HYPERELASTIC (same energies and data lines as Abaqus; OGDEN N ≤ 3)"
MAPPINGS = {k: Mapping(m.keyword, m.volumetric, _MANUAL, 3 if k == "ogden" else m.max_terms)
            for k, m in abaqus.MAPPINGS.items()}
NOTES = {"gent": "CalculiX has no Gent model", "neo-hookean": abaqus.NOTES["neo-hookean"].replace("Abaqus", "CalculiX")}


def write(card, units) -> str:
    return abaqus.write_deck(card, units, "calculix", MAPPINGS, _MANUAL)


def read(text: str, where: str, units):
    card = abaqus.read_deck(text, where, units)
    if card.model == "ogden" and card.terms > 3:
        from vlab.export.registry import CardFormatError

        raise CardFormatError(f"{where}: CalculiX' OGDEN allows N ≤ 3, the card has N = {card.terms}")
    return card


CALCULIX = Exporter("calculix", "calculix.inp", "**", MAPPINGS, write, read, notes=NOTES, doc=__doc__)
