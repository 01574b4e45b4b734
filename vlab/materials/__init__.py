"""Hyperelastic material models and their registry.

``MODELS`` (vlab.materials.registry) is the one list of models: name -> ``Model`` entry (card
constants, build, split law, capabilities). ``build_material(spec)`` builds the law of a
validated card (vlab.materials.card); ``make_material(model, lmbda, mu)`` builds one of the
models parametrised by their Lamé constants (``LAME_MODELS``). See :mod:`vlab.materials.base`
for the shared contract (energy/stress/tangent on F of shape (3, 3, *batch)).
"""

from __future__ import annotations

from vlab.materials.base import Material
from vlab.materials.card import build_material, build_split_law
from vlab.materials.linear import LinearElastic
from vlab.materials.neo_hookean import NeoHookean
from vlab.materials.registry import MODELS, MaterialCard, Model, models_where
from vlab.materials.stvk import StVenantKirchhoff
from vlab.materials.stvk_volumetric import StVKVolumetric

__all__ = [
    "MODELS",
    "LAME_MODELS",
    "CARD_MODELS",
    "Model",
    "make_material",
    "build_material",
    "build_split_law",
    "Material",
    "LinearElastic",
    "StVenantKirchhoff",
    "StVKVolumetric",
    "NeoHookean",
]

#: continuum models given by two elastic constants (the Lamé pair)
LAME_MODELS: tuple[str, ...] = models_where(lambda m: m.continuum and m.constants is None)
#: models given by a material card of their own constants (plus K | D1 | nu)
CARD_MODELS: tuple[str, ...] = models_where(lambda m: m.constants is not None)


def make_material(model: str, lmbda: float, mu: float) -> Material:
    """Build the material ``model`` (one of ``LAME_MODELS``) with Lamé constants ``lmbda``, ``mu`` (MPa).

    Raises ValueError naming ``material.model`` and listing the allowed names if ``model`` is
    unknown or is not given by two elastic constants (and ValueError from the model if the
    constants are not admissible).
    """
    if model not in LAME_MODELS:
        allowed = ", ".join(repr(n) for n in LAME_MODELS)
        raise ValueError(f"unknown material.model {model!r} for two Lamé constants; allowed: {allowed} "
                         f"(card models {', '.join(CARD_MODELS)}: build_material)")
    return MODELS[model].build(MaterialCard(model, _Lame(lmbda, mu)))


class _Lame:
    """The Lamé constants as given (the law validates them; its message names why)."""

    def __init__(self, lmbda: float, mu: float):
        self.lmbda, self.mu = lmbda, mu
