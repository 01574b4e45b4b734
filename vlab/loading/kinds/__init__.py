"""The registry of test kinds a scene may ask for with ``[test] kind``.

A test kind is everything that differs between a uniaxial, a biaxial, a planar (pure-shear) and a
simple-shear test, in one object, so that no code outside this package asks how long a stretch
list is. Each entry of ``KINDS`` (a :class:`~vlab.loading.kinds.base.TestKind`) says, for one
name:

- **grammar**: ``load_key`` (the [test] key of its load: ``stretch`` or ``shear``) and
  ``parse_load(table, protocol) -> targets``, the control values at load parameter t = 1 (the
  grip stretches (λ,), (λx, λy), or the amount of shear (γ,)); every error is a SceneError naming
  ``test.<key>`` and the allowed range; ``check(test)`` refuses what the kind cannot run
  (a creep force, an imperfection, effects);
- **grips**: ``loading(specimen, X, test) -> GripLoading`` (prescribed DOFs, their values at
  t = 1, the moving grip's DOFs per load cell) and ``at(targets, t)`` (the control values at t:
  λ(t) = 1 + t (λ − 1), or γ(t) = t γ), ``grip_strain(targets)`` (λ − 1 or γ: what the load
  schedule and the protocol's rates count), ``describe(values)`` (text for messages);
- **oracle**: ``state(material, values) -> HomogeneousState`` (materials.homogeneous: the exact
  homogeneous state on the kind's oracle set-up, ``oracle_setups`` = {shape: grips}; raises
  InadmissibleState when none exists), and ``reference(material, curve)`` (its curve at the
  recorded rows);
- **instruments**, declared by name and provided by the measure layer (vlab/measure/kinds.py:
  a kind never imports it): ``axes`` (the load cells recorded, by axis), ``areas(specimen)``
  (each load cell's reference area), ``gauge`` (the strain instruments: "extensometers" along
  each loaded axis with width and thickness, or "shear-gauge"), ``readers`` (other readings, e.g.
  "normal-force" on a shear plate, "centre-cauchy": the FE centre stress) and ``field_probe``
  (the field statistics of results.json → homogeneity: "gauge-section" of a dogbone,
  "pure-shear", "simple-shear");
- **measures**, by name likewise: ``fit`` ("uniaxial": E, ν; "biaxial": the biaxial constants;
  "planar": the planar modulus E/(1 − ν²); "shear": the shear modulus G and the normal-stress
  difference, in ``extra``), each over the stated window with its fit quality; ``crosshead_fit``
  ("crosshead", uniaxial: the modulus from grip strain), ``measured_units``;
- **results and report**: ``columns(curve)`` and ``units`` (results.json → curve),
  ``control_name`` (the renders' titles: "grip stretch", "shear", "inner hoop stretch") with
  ``rest`` (the control at rest: 1 for a stretch, 0 for γ or a twist),
  ``force_column`` / ``control_column``, ``plot`` (the report's axes and labels),
  ``measures_E`` and ``lateral_ratio`` (whether E, ν and the apparent Poisson's ratio mean
  something), ``cyclic``, ``effects`` and ``symmetric`` (what the scene may combine it with).

Adding a kind is one module here defining its TestKind and one ``register`` call below; the
specimen shapes that can run it say so in their registry entry (vlab/geometry/shapes.py). A kind
that measures with the existing instruments and fits names them; a new instrument or fit is one
function in vlab/measure/ and one entry in the tables of vlab/measure/kinds.py.
"""

from __future__ import annotations

from vlab.loading.kinds.base import TestKind

__all__ = ["KINDS", "TestKind", "kind_of", "peak_grip_strain", "register", "run_levels"]

KINDS: dict[str, TestKind] = {}


def register(kind: TestKind) -> TestKind:
    KINDS[kind.name] = kind
    return kind


def kind_of(test) -> TestKind:
    """The kind of a TestSpec (its variant for the test's options: ``TestKind.for_test``), or of a
    kind name."""
    if isinstance(test, str):
        return KINDS[test]
    return KINDS[test.kind].for_test(test)


def peak_grip_strain(test) -> float:
    """The largest |grip strain| of a TestSpec at t = 1 (λ − 1 of any grip, or γ): what an
    effect's caveats compare with its own strain or time scales, whatever the kind."""
    return max(abs(g) for g in kind_of(test).grip_strain(test.targets))


def run_levels(scene):
    """The levels a scene's test runs at (vlab.loading.protocol.Levels): its protocol's over the
    kind's grip strain, with the modulus window's, and the kind's own (``TestKind.scheduled``:
    a phase before the protocol, a finer start) for the scene's specimen spec."""
    from vlab.loading.protocol import protocol_levels

    test, m = scene.test, scene.measure
    kind = kind_of(test)
    grip_stretch = tuple(1.0 + g for g in kind.grip_strain(test.targets))
    levels = protocol_levels(test.protocol, grip_stretch, test.steps, m.modulus_window, m.modulus_points)
    return kind.scheduled(levels, test, scene.specimen)


def _register_builtins() -> None:
    from vlab.loading.kinds.biaxial import BIAXIAL
    from vlab.loading.kinds.confined import CONFINED
    from vlab.loading.kinds.inflation import INFLATION
    from vlab.loading.kinds.planar import PLANAR
    from vlab.loading.kinds.simple_shear import SIMPLE_SHEAR
    from vlab.loading.kinds.torsion import TORSION
    from vlab.loading.kinds.uniaxial import UNIAXIAL

    for kind in (UNIAXIAL, BIAXIAL, PLANAR, SIMPLE_SHEAR, CONFINED, TORSION, INFLATION):
        register(kind)


_register_builtins()
