"""Stage 1 of a run: the specimen's mesh (checked), its displacement space, the body the scene's
material and formulation ask for, the grips' prescribed displacements and the DOF partition."""

from __future__ import annotations

from dataclasses import dataclass

from vlab.fe.assembly import Partition
from vlab.fe.mixed import MixedHyperelasticBody
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.fe.spring_network import SpringNetwork
from vlab.geometry.mesh_check import MeshError, check_mesh
from vlab.geometry.quality import MeshQuality, mesh_quality
from vlab.geometry.shapes import SHAPES
from vlab.geometry.specimen import Specimen
from vlab.loading.grips import GripLoading
from vlab.loading.kinds import kind_of
from vlab.materials import MODELS, build_material, build_split_law
from vlab.materials.base import Material
from vlab.materials.history import HistoryMaterial
from vlab.materials.plane import plane_model
from vlab.scene import Scene, SceneError
from vlab.settings import Settings

__all__ = ["Prepared", "MeshQualityError", "prepare", "build_specimen", "checked_quality", "make_body"]


class MeshQualityError(SceneError):
    """The mesh's worst element is below the scene's ``mesh.min_quality``."""


@dataclass(frozen=True)
class Prepared:
    """A test ready to solve.

    ``ground`` is the elastic law the admissibility check reads (a history law's ground law);
    ``oracle`` the material of the analytic homogeneous checks, None where they do not apply
    (the spring network, a history law, a dead load)."""

    scene: Scene
    specimen: Specimen
    quality: MeshQuality
    space: DisplacementSpace
    body: object  # vlab.fe.body.Body
    loading: GripLoading
    partition: Partition
    ground: Material | None
    oracle: Material | None


def prepare(scene: Scene, specimen: Specimen | None = None, settings: Settings | None = None) -> Prepared:
    """Mesh (or take ``specimen``), check, build the space, body, grips and partition; ``settings``
    (vlab.settings: the kernel and assembly threads) go to the body (None: the installed ones)."""
    specimen = specimen or build_specimen(scene)
    quality = checked_quality(scene, specimen)
    space = DisplacementSpace.build(specimen.mesh, scene.mesh.order, specimen.sheet_thickness or 1.0)
    body = make_body(scene, space, settings)
    material = body.material  # None for the spring network: no analytic oracle
    ground = material.elastic if isinstance(material, HistoryMaterial) else material  # its ground law
    oracle = material
    if isinstance(material, HistoryMaterial) or scene.effect("gravity") is not None:
        oracle = None  # a history law or a dead load: the elastic homogeneous oracles do not apply
    loading = kind_of(scene.test).loading(specimen, space.node_coordinates, scene.test)
    if loading.liquid is not None:  # the load is a liquid's pressure on a face (the bulge test)
        from vlab.fe.liquid import LiquidBody

        body = LiquidBody(body, loading.liquid)
    partition = Partition.build(body.pattern, loading.prescribed)
    return Prepared(scene, specimen, quality, space, body, loading, partition, ground, oracle)


def build_specimen(scene: Scene) -> Specimen:
    """The specimen mesh (its shape's ``build``: vlab/geometry/shapes.py); first the size budget
    (SceneError before anything is allocated)."""
    from vlab.fe.iterative import choose
    from vlab.fe.linsolve import solver_in_use
    from vlab.geometry.budget import check_budget

    check_budget(scene, lambda dofs: choose(scene.solver.linear, dofs, solver_in_use()))
    return SHAPES[scene.specimen.shape].build(scene.specimen, scene.mesh, scene.measure.gauge_length)


def checked_quality(scene: Scene, specimen: Specimen) -> MeshQuality:
    """The mesh's quality; MeshQualityError if the mesh is invalid (inverted or flat elements,
    duplicate or unused nodes) or its worst element is below mesh.min_quality."""
    try:
        check_mesh(specimen.mesh)
    except MeshError as exc:
        raise MeshQualityError(f"invalid mesh: {exc}") from None
    quality = mesh_quality(specimen.mesh)
    if quality.min_quality < scene.mesh.min_quality:
        raise MeshQualityError(
            f"mesh.min_quality: {_mesh_name(specimen.shape)}'s worst element (#{quality.worst_element}) has "
            f"{quality.measure} quality {quality.min_quality:.3g} < mesh.min_quality = "
            f"{scene.mesh.min_quality:g} (1 is ideal; max aspect ratio {quality.max_aspect_ratio:.3g}); "
            f"change mesh.size / mesh.cell, or lower mesh.min_quality")
    return quality


def _mesh_name(shape: str) -> str:
    """How a message names a specimen's mesh: "the dogbone mesh", but "the imported mesh" for
    shape = "mesh" (not "the mesh mesh")."""
    return "the imported mesh" if shape == "mesh" else f"the {shape} mesh"


def make_body(scene: Scene, space: DisplacementSpace, settings: Settings | None = None):
    """The body a scene's material.model and mesh.formulation ask for: a continuum material
    (displacement-only or mixed θ/p condensed per element), on a 2D space (a sheet) the
    material's plane-stress or plane-strain reduction, or the spring network."""
    moduli = scene.material.moduli
    if not MODELS[scene.material.model].continuum:
        return SpringNetwork(space, moduli.E)
    if scene.mesh.formulation == "mixed":
        return MixedHyperelasticBody(space, build_split_law(scene.material), settings=settings)
    elastic = build_material(scene.material)
    if space.dim == 2:
        elastic = plane_model(elastic, scene.specimen.plane)
    if not scene.effects:  # the elastic path: nothing else is built or assembled
        return HyperelasticBody(space, elastic, settings=settings)
    from vlab.effects.build import external_load, history_law
    from vlab.fe.external_load import LoadedBody
    from vlab.fe.history_body import HistoryBody
    law = history_law(scene, elastic)
    body = HistoryBody(space, law) if law is not None else HyperelasticBody(space, elastic, settings=settings)
    f_ext = external_load(scene, space)
    return body if f_ext is None else LoadedBody(body, f_ext)
