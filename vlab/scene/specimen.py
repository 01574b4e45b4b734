"""``[specimen]``: delegates to the specimen-shape registry (vlab/geometry/shapes.py).

Each shape owns its spec dataclass (with ``length`` and ``max_dimension``, mm), its parser, its
mesh and the test kinds and grips it allows, in its geometry module: block, dogbone (standard or
explicit dimensions), sheet (2D, plane stress or strain), cruciform, mesh (a user's file),
planar-tension (a wide strip, width/height ≥ 10), shear (a layer between rigid plates) and
double-lap (two layers between three plates).
"""

from __future__ import annotations

from typing import Any

from vlab import fields
from vlab.fields import SceneError
from vlab.geometry.block import BlockSpecimen
from vlab.geometry.cruciform import CruciformSpecimen
from vlab.geometry.dogbone import DogboneSpecimen
from vlab.geometry.double_lap import DoubleLapSpecimen
from vlab.geometry.imported import MESH_FILE_KEYS, SCENE_DIR, MeshFileSpecimen
from vlab.geometry.planar import PlanarSpecimen
from vlab.geometry.shapes import SHAPES
from vlab.geometry.shear import ShearSpecimen
from vlab.geometry.sheet import SheetSpecimen

__all__ = ["BlockSpecimen", "DogboneSpecimen", "SheetSpecimen", "CruciformSpecimen", "MeshFileSpecimen",
           "PlanarSpecimen", "ShearSpecimen", "DoubleLapSpecimen", "Specimen", "SHAPES", "SPECIMEN_TESTS", "SYMMETRIC_SHAPES",
           "MESH_FILE_KEYS", "SCENE_DIR", "parse_specimen"]

Specimen = (BlockSpecimen | DogboneSpecimen | SheetSpecimen | CruciformSpecimen | MeshFileSpecimen
            | PlanarSpecimen | ShearSpecimen | DoubleLapSpecimen)
# views of the registry: shape -> {test kind: grips (the first the default)}; mirror-built shapes
SPECIMEN_TESTS: dict[str, dict[str, tuple[str, ...]]] = {name: s.tests for name, s in SHAPES.items()}
SYMMETRIC_SHAPES = tuple(name for name, s in SHAPES.items() if s.symmetric)
FINE_MESH_SHAPES = tuple(name for name, s in SHAPES.items() if s.gauge_size)  # shapes with a [mesh] gauge_size


def parse_specimen(raw: Any) -> Specimen:
    if not isinstance(raw, dict):
        raise SceneError(f"[specimen] must be a table, got {fields.show(raw)}")
    if "shape" not in raw:
        raise SceneError("missing required key specimen.shape")
    shape = SHAPES[fields.choice("specimen.shape", raw["shape"], tuple(SHAPES))]
    return shape.parse(fields.Table("specimen", raw, ("shape",) + shape.keys))
