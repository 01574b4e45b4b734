"""Effects a scene can switch on (``[effects]``): see vlab.effects.registry for the contract."""

from __future__ import annotations

from vlab.effects import gravity, viscoelastic
from vlab.effects.registry import EFFECTS, Effect, register

register(viscoelastic.EFFECT)
register(gravity.EFFECT)

__all__ = ["EFFECTS", "Effect", "register"]
