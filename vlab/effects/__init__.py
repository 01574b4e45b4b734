"""Effects a scene can switch on (``[effects]``): see vlab.effects.registry for the contract."""

from __future__ import annotations

from vlab.effects import gravity, mullins, noise, plasticity, viscoelastic
from vlab.effects.registry import COMBINED, EFFECTS, Effect, register, register_combined

register(viscoelastic.EFFECT)
register(gravity.EFFECT)
register(plasticity.EFFECT)
register(mullins.EFFECT)
register(noise.EFFECT)


def _softened_viscoelastic(specs: dict, elastic):
    """[effects.viscoelastic] with [effects.mullins]: the softened long-term response plus the
    Maxwell branches (vlab.materials.softened_viscoelastic)."""
    from vlab.materials.softened_viscoelastic import SoftenedViscoelastic

    return SoftenedViscoelastic(elastic, mullins=mullins.build(specs["mullins"], elastic),
                                prony=viscoelastic.build(specs["viscoelastic"], elastic))


register_combined(("viscoelastic", "mullins"), _softened_viscoelastic)

__all__ = ["EFFECTS", "COMBINED", "Effect", "register", "register_combined"]
