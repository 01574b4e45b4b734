"""Hyperelastic material models and their registry.

``MODELS`` maps a model name (as written in a scene's ``material.model``) to its class;
``make_material(model, lmbda, mu)`` builds one. See :mod:`vlab.materials.base` for the
shared contract (energy/stress/tangent on F of shape (3, 3, *batch)).
"""

from __future__ import annotations

from vlab.materials.base import Material
from vlab.materials.linear import LinearElastic
from vlab.materials.neo_hookean import NeoHookean
from vlab.materials.stvk import StVenantKirchhoff
from vlab.materials.stvk_volumetric import StVKVolumetric

__all__ = [
    "MODELS",
    "make_material",
    "Material",
    "LinearElastic",
    "StVenantKirchhoff",
    "StVKVolumetric",
    "NeoHookean",
]

#: Registry: model name -> class.
MODELS: dict[str, type] = {
    cls.name: cls for cls in (LinearElastic, StVenantKirchhoff, StVKVolumetric, NeoHookean)
}


def make_material(model: str, lmbda: float, mu: float) -> Material:
    """Build the material ``model`` with Lamé constants ``lmbda``, ``mu`` (MPa).

    Raises ValueError naming ``material.model`` and listing the allowed names if ``model`` is
    unknown (and ValueError from the model if the constants are not admissible).
    """
    try:
        cls = MODELS[model]
    except (KeyError, TypeError):
        allowed = ", ".join(repr(n) for n in MODELS)
        raise ValueError(f"unknown material.model {model!r}; allowed: {allowed}") from None
    return cls(lmbda=lmbda, mu=mu)
