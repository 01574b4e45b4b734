"""From a scene's declared effects to what the solver and the report use (nothing if none)."""

from __future__ import annotations


from vlab.effects.registry import COMBINED, EFFECTS



def history_law(scene, elastic):
    """The HistoryMaterial wrapping ``elastic`` if a "material" effect is declared (or a set of
    them with one law in COMBINED), else None."""
    specs = {s.name: s for s in scene.effects if EFFECTS[s.name].role == "material"}
    if len(specs) > 1:
        return COMBINED[frozenset(specs)](specs, elastic)
    for name, spec in specs.items():
        return EFFECTS[name].build(spec, elastic)
    return None


def external_load(scene, space):
    """The summed dead-load vector f_ext (N) of the declared "load" effects, else None."""
    total = None
    for spec in scene.effects:
        effect = EFFECTS[spec.name]
        if effect.role == "load":
            f = effect.build(spec, scene, space)
            total = f if total is None else total + f
    return total


def effect_warnings(scene) -> list[str]:
    """Caveats: effects that cannot show in this set-up, protocols that show nothing here."""
    found = []
    for spec in scene.effects:
        found += EFFECTS[spec.name].warnings(spec, scene.material, scene.test)
    rate_dependent = any(EFFECTS[s.name].timed for s in scene.effects)
    protocol = scene.test.protocol
    if protocol.has_hold and not rate_dependent:
        found.append(f"test.protocol = {protocol.name!r} holds for {protocol.hold_time:g} s, but no declared "
                     "effect is rate-dependent: an elastic specimen neither relaxes nor creeps, the hold "
                     "records a constant state")
    if protocol.unloads and not scene.effects:
        found.append(f"test.protocol = {protocol.name!r} on an elastic material: unloading retraces "
                     "loading (no hysteresis, no permanent set)")
    return found  # logged once by the caller (vlab.run._warnings), with the run's other warnings
