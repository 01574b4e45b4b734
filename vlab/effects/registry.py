"""The registry of effects a scene may switch on in its ``[effects]`` section.

An effect is a table ``[effects.<name>]`` with its parameters. Absent effects are not simulated
and cost nothing: an elastic scene builds the same body, assembles the same terms and runs the
same stepping loop as before effects existed.

Each entry of ``EFFECTS`` says, for one name:

- ``keys``: the allowed keys of its table (anything else is a SceneError naming the key);
- ``parse(table, material, test) -> spec``: validates the table into a frozen spec dataclass
  (every error names ``effects.<name>.<key>``, the allowed range and what was got);
- ``role``: what it changes — ``"material"`` (a history-dependent law wrapping the elastic
  ground law: ``build(spec, elastic) -> HistoryMaterial``), ``"load"`` (an external load:
  ``build(spec, scene, space) -> f_ext`` in N) or ``"measure"`` (instruments; ``build(spec)``);
- ``protocols``: the test protocols that can show the effect (others are a SceneError that says
  why, e.g. the Mullins effect needs unloading), ``None`` for any;
- ``timed``: True if the effect makes the response rate-dependent, so the scene must give time
  (``test.strain_rate`` or ``test.ramp_time``);
- ``models``: the material models a ``"material"`` effect can wrap, asked of the model registry
  (vlab.materials.registry.models_where): by default every continuum model;
- ``warnings(spec, material, test) -> list[str]``: caveats written to results.json (an effect
  whose every parameter is inert, for instance).

Adding an effect is one entry here and one ``register`` call in vlab/effects/__init__.py.
At most one ``"material"`` effect per scene (one history law wraps the ground law), unless
``COMBINED`` has a law for the set of them: ``register_combined(names, build)`` with
``build({name: spec}, elastic) -> HistoryMaterial`` the one law of those effects together over the
ground law (viscoelastic with mullins: vlab.materials.softened_viscoelastic). A combination also
meets each of its effects' protocols, time and ground-law models.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from vlab.materials.registry import models_where

__all__ = ["Effect", "EFFECTS", "COMBINED", "register", "register_combined"]


def _no_warnings(spec, material, test) -> list[str]:
    return []


@dataclass(frozen=True)
class Effect:
    name: str
    keys: tuple[str, ...]
    parse: Callable[..., Any]
    role: str  # "material" | "load" | "measure"
    build: Callable[..., Any]
    protocols: tuple[str, ...] | None = None
    timed: bool = False
    models: tuple[str, ...] = field(default_factory=lambda: models_where(lambda m: m.continuum))  # ground laws it wraps
    warnings: Callable[..., list[str]] = _no_warnings
    doc: str = ""


EFFECTS: dict[str, Effect] = {}
COMBINED: dict[frozenset, Callable[..., Any]] = {}  # a set of "material" effects -> build of their one law


def register(effect: Effect) -> Effect:
    if effect.role not in ("material", "load", "measure"):
        raise ValueError(f"effect {effect.name!r}: role must be material, load or measure, got {effect.role!r}")
    EFFECTS[effect.name] = effect
    return effect


def register_combined(names: tuple[str, ...], build: Callable[..., Any]) -> None:
    """Let the "material" effects ``names`` be declared together, as the one law ``build`` makes."""
    if any(EFFECTS[n].role != "material" for n in names):
        raise ValueError(f"register_combined: {', '.join(names)} must all be material effects")
    COMBINED[frozenset(names)] = build
