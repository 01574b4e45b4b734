"""``[effects]``: each ``[effects.<name>]`` table is validated by its effect's own parser
(vlab.effects; the registry's contract is in vlab/effects/registry.py); here only what concerns
the scene as a whole: where effects apply, their protocols, time, and one history law at most."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from vlab import fields
from vlab.effects import COMBINED, EFFECTS
from vlab.fields import SceneError
from vlab.scene.material import continuum

if TYPE_CHECKING:
    from vlab.scene.material import MaterialSpec
    from vlab.scene.mesh import MeshSpec
    from vlab.scene.test import TestSpec

__all__ = ["parse_effects", "check_effects_scope"]


def check_effects_scope(raw: Any, shape: str, mesh: MeshSpec, model: str) -> None:
    """Effects run on displacement-formulation 3D continua only: say so instead of ignoring them."""
    if not raw or not isinstance(raw, dict):
        return
    name = f"effects.{next(iter(raw))}"
    if not continuum(model):
        raise SceneError(f"{name}: material.model {model!r} is a network of springs without "
                         f"effects; use a continuum model with [effects]")
    if shape == "sheet":
        raise SceneError(f"{name}: [effects] are not available on specimen.shape = 'sheet' (2D) in "
                         f"this build; use a block or a dogbone")
    if mesh.formulation == "mixed":
        raise SceneError(f"{name}: [effects] need mesh.formulation = 'displacement' in this build "
                         f"(the mixed formulation wraps split elastic laws only)")


def parse_effects(raw: Any, material: MaterialSpec, test: TestSpec) -> tuple:
    """[effects.<name>] tables -> effect specs, validated by the registry (vlab.effects)."""
    if not isinstance(raw, dict):
        raise SceneError(f"[effects] must be a table of effects, got {fields.show(raw)}")
    specs = []
    for name, table in raw.items():
        if name not in EFFECTS:
            raise SceneError(f"unknown effect effects.{name} (allowed: {', '.join(EFFECTS)})"
                             f"{fields.suggest(name, EFFECTS)}")
        effect = EFFECTS[name]
        spec = effect.parse(fields.Table(f"effects.{name}", table, effect.keys), material, test)
        if effect.protocols is not None and test.protocol.name not in effect.protocols:
            raise SceneError(f"effects.{name} cannot show with test.protocol = {test.protocol.name!r}: "
                             f"use one of {', '.join(effect.protocols)}")
        if effect.timed and not test.protocol.timed:
            raise SceneError(f"effects.{name} makes the test rate-dependent: give test.strain_rate "
                             f"(1/s) or test.ramp_time (s)")
        specs.append(spec)
    laws = [s.name for s in specs if EFFECTS[s.name].role == "material"]
    if len(laws) > 1 and frozenset(laws) not in COMBINED:
        pairs = " or ".join(" with ".join(sorted(c)) for c in COMBINED)
        raise SceneError(f"effects: one history-dependent law at a time, got {', '.join(laws)}"
                         + (f" (combined: {pairs})" if pairs else ""))
    for law in laws:
        if material.model not in EFFECTS[law].models:
            raise SceneError(f"effects.{law} wraps material.model = one of "
                             f"{', '.join(EFFECTS[law].models)}, got {material.model!r}")
    return tuple(specs)
