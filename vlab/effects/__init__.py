"""Effects a scene can switch on (``[effects]``): see vlab.effects.registry for the contract."""

from __future__ import annotations

from vlab.effects import gravity, mullins, noise, plasticity, viscoelastic
from vlab.effects.registry import EFFECTS, Effect, register

register(viscoelastic.EFFECT)
register(gravity.EFFECT)
register(plasticity.EFFECT)
register(mullins.EFFECT)
register(noise.EFFECT)

__all__ = ["EFFECTS", "Effect", "register"]
