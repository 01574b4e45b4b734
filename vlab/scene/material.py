"""``[material]`` and ``[compare.<label>]``: material cards in the grammar of the model registry.

The grammar lives with the models (vlab.materials.registry lists them, vlab.materials.card
validates a card): a model with constants takes exactly those keys plus one of K | D1 | nu and an
optional ``volumetric``; the Lamé-pair models take any two of E, nu, lambda, mu/G, K, M
(``root`` picks the (E, M) root); all take ``density`` (kg/m³, stored in t/mm³). Each
``[compare.<label>]`` table is one more card, run side by side by ``vlab compare``.
"""

from __future__ import annotations

from typing import Any

from vlab import fields
from vlab.fields import SceneError
from vlab.materials.card import KG_PER_M3, MaterialSpec, check_path
from vlab.materials.card import parse_material as parse_card
from vlab.materials.registry import MODELS as REGISTRY

__all__ = ["MaterialSpec", "MODELS", "SPRING_NETWORK", "KG_PER_M3", "parse_material", "parse_compare",
           "check_path", "continuum"]

SPRING_NETWORK = "spring-network"  # not a material law: mesh edges as springs (vlab.fe.spring_network)
MODELS = tuple(REGISTRY)  # the model registry's names (vlab.materials.registry)


def parse_material(raw: Any) -> MaterialSpec:
    """[material]: one card (vlab.materials.card)."""
    return parse_card(raw, "material")


def parse_compare(raw: Any) -> dict[str, MaterialSpec]:
    """[compare.<label>] tables: one material card each (the label names a report folder)."""
    import re

    if not isinstance(raw, dict):
        raise SceneError(f"[compare] must be a table of material cards [compare.<label>], got {fields.show(raw)}")
    cards = {}
    for label, card in raw.items():
        if not re.fullmatch(r"[A-Za-z0-9._-]+", label) or set(label) == {"."}:
            raise SceneError(f"compare.{label}: a label must match [A-Za-z0-9._-]+ (it names a report folder)")
        cards[label] = parse_card(card, f"compare.{label}")
    return cards


def continuum(model: str) -> bool:
    """False for a model that is a body, not a law (the spring network)."""
    return REGISTRY[model].continuum
