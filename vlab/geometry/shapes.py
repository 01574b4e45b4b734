"""The registry of specimen shapes a scene may ask for with ``[specimen] shape``.

Each entry (a :class:`Shape`) says, for one name, everything the scene and the run need to know
about the shape, next to its geometry (the module that meshes it):

- ``keys``: the allowed keys of [specimen] besides ``shape`` (anything else is a SceneError);
- ``parse(table) -> spec``: validates the table (vlab.fields.Table) into a frozen spec dataclass
  with ``shape``, ``length`` (mm, along the first loading axis: bounds measure.gauge_length) and
  ``max_dimension`` (mm: bounds mesh.size); a GeometryError of impossible dimensions becomes a
  SceneError naming ``specimen.<key>`` and its range;
- ``build(spec, mesh, gauge_length) -> Specimen``: the meshed specimen with its named grips,
  gauge marks and regions (``mesh`` the scene's MeshSpec), and optionally its ``view``
  (vlab.geometry.specimen.View: the direction a lab photographs it from, screen up, the rigid
  plates the renders draw; None: the renders' default direction);
- ``tests``: {test kind: grips it can run with}, the first grips the default (vlab.loading.kinds);
- ``symmetric``: its mesh is built mirror-symmetric, so [mesh] symmetry may reduce it;
  ``gauge_size``: it takes a finer [mesh] gauge_size over its gauge section;
- ``gauge_from``: None when ``build`` places the extensometer over ``gauge_length`` (the scene's
  measure.gauge_length); else where its gauge marks come from (a standard's marks, the file's
  ``gauge_marks``, no extensometer), and measure.gauge_length is refused naming it;
- ``thickness(spec) -> mm``: the smallest cross-section dimension, the scale of a buckling
  imperfection (None: test.imperfection does not apply);
- ``count(spec, mesh) -> MeshCount``: elements, nodes and dimension of the mesh ``build`` would
  make, by arithmetic on the dimensions before anything is meshed (vlab.geometry.counts has the
  structured-lattice rules): the size budget (vlab/geometry/budget.py) reads it, and every shape
  must have one (tests/test_budget.py checks the registry).

Adding a shape is one module (its spec dataclass, parser, mesh and the ``SHAPE`` entry) and one
line in ``_BUILTIN`` below.
"""

from __future__ import annotations

from importlib import import_module

from vlab.geometry.shape import Shape

__all__ = ["Shape", "SHAPES", "register", "build_specimen"]


SHAPES: dict[str, Shape] = {}


def register(shape: Shape) -> Shape:
    SHAPES[shape.name] = shape
    return shape


def build_specimen(spec, mesh, gauge_length: float | None):
    """The meshed Specimen of a parsed spec (its shape's ``build``)."""
    return SHAPES[spec.shape].build(spec, mesh, gauge_length)


_BUILTIN = ("block", "dogbone", "sheet", "cruciform", "imported", "planar", "shear", "double_lap", "cad_specimen",
            "cylinder", "sphere_shell", "membrane")  # vlab.geometry.<module>.SHAPE

for _module in _BUILTIN:
    register(import_module(f"vlab.geometry.{_module}").SHAPE)
