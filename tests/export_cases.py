"""The cards the export tests write: every model (Ogden with 1 … 6 terms) and, per target, the
card with the volumetric form that target uses (an incompressible fit's stand-in where the
target's U(J) is none of vlab's)."""

from __future__ import annotations

from dataclasses import replace

from vlab.export import EXPORTERS
from vlab.export.card import card_from_table
from vlab.export.registry import refusal
from vlab.materials.volumetric import VOLUMETRIC

_PAIRS = [(0.63, 1.3), (0.0012, 5.0), (-0.01, -2.0), (0.05, 3.1), (-0.002, -4.2), (0.1, 0.8)]
TABLES = {
    "neo-hookean": {"model": "neo-hookean", "mu": 0.41, "K": 97.3},
    "mooney-rivlin": {"model": "mooney-rivlin", "C10": 0.31, "C01": 0.047, "K": 103.7},
    "yeoh": {"model": "yeoh", "C10": 0.28, "C20": -0.0123, "C30": 0.00041, "K": 88.1},
    "arruda-boyce": {"model": "arruda-boyce", "mu": 0.27, "lambda_m": 2.8, "K": 120.0},
    "gent": {"model": "gent", "mu": 0.3, "Jm": 42.0, "K": 150.0},
}
for _n in range(1, 7):
    TABLES[f"ogden-{_n}"] = {"model": "ogden", "mu": [m for m, _ in _PAIRS[:_n]],
                             "alpha": [a for _, a in _PAIRS[:_n]], "K": 77.7}
LABELS = tuple(TABLES)
TARGETS = tuple(EXPORTERS)


def base_card(label: str, volumetric: str | None = None, density: float | None = 1100.0):
    t = dict(TABLES[label])
    if volumetric is not None and t["model"] != "neo-hookean":
        t["volumetric"] = volumetric
    if density is not None:
        t["density"] = density
    return card_from_table(t, label, name=label)


def card_for(label: str, target: str):
    """The card of ``label`` in the volumetric form ``target`` uses, or None if refused."""
    model = TABLES[label]["model"]
    m = EXPORTERS[target].models.get(model)
    if m is None:
        return None
    if m.volumetric is None or m.volumetric in VOLUMETRIC:
        card = base_card(label, m.volumetric)
    else:
        card = replace(base_card(label), stand_in=True)
    return None if refusal(target, card) else card


PAIRS = [(label, target) for label in LABELS for target in TARGETS if card_for(label, target) is not None]
REFUSED = [(label, target) for label in LABELS for target in TARGETS if card_for(label, target) is None]
