"""Scene files (TOML) -> validated, frozen dataclasses.

A scene describes one virtual test: specimen, mesh, material, loading, measurement, solver,
effects. Required: ``name``, [specimen] shape + its dimensions, [mesh] size, [material] model +
exactly two elastic constants, [test] kind + stretch. Unknown sections and keys are errors; every
:class:`SceneError` names the dotted field, the allowed values and what was got.

One module per section (specimen, mesh, material, test, measure, solver, effects), the whole
scene and its entry points in ``load``, dotted-key overrides in ``overrides``. The package is the
file format only: it imports no solver (parsing a scene loads neither vlab.fe nor numba; a test
asserts it), and its section parsers delegate to the registries below it (shapes in
vlab.geometry, test kinds in vlab.loading, models in vlab.materials, effects in vlab.effects).
"""

from __future__ import annotations

from vlab.fields import SceneError
from vlab.scene.load import SECTIONS, TOP_KEYS, Scene, load_scene, parse_scene
from vlab.scene.material import KG_PER_M3, MODELS, SPRING_NETWORK, MaterialSpec
from vlab.scene.measure import MeasureSpec
from vlab.scene.mesh import FORMULATIONS, MeshSpec
from vlab.scene.overrides import apply_overrides
from vlab.scene.solver import SolverSpec
from vlab.scene.specimen import (MESH_FILE_KEYS, SPECIMEN_SHAPES, SPECIMEN_TESTS, SYMMETRIC_SHAPES, BlockSpecimen,
                                 CruciformSpecimen, DogboneSpecimen, MeshFileSpecimen, SheetSpecimen, Specimen)
from vlab.scene.test import PROTOCOL_KEYS, TestSpec

__all__ = ["SceneError", "Scene", "BlockSpecimen", "DogboneSpecimen", "SheetSpecimen", "CruciformSpecimen",
           "MeshFileSpecimen", "Specimen", "MeshSpec", "MaterialSpec", "TestSpec", "MeasureSpec", "SolverSpec",
           "load_scene", "parse_scene", "apply_overrides", "SPECIMEN_SHAPES", "SPECIMEN_TESTS", "SYMMETRIC_SHAPES",
           "MESH_FILE_KEYS", "MODELS", "SPRING_NETWORK", "KG_PER_M3", "FORMULATIONS", "PROTOCOL_KEYS", "SECTIONS",
           "TOP_KEYS"]
