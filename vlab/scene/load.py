"""A whole scene: the top-level keys, the :class:`Scene` dataclass and the entry points
:func:`parse_scene` (a dict) and :func:`load_scene` (a TOML file). Each section is parsed by its
own module of this package."""

from __future__ import annotations

import copy
import hashlib
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from vlab import fields
from vlab.fields import SceneError
from vlab.loading.kinds import kind_of
from vlab.scene.effects import check_effects_scope, parse_effects
from vlab.scene.instruments import parse_instruments
from vlab.scene.material import check_path, continuum, parse_compare, parse_material
from vlab.scene.measure import parse_measure
from vlab.scene.mesh import check_formulation, check_symmetry, parse_mesh
from vlab.scene.solver import parse_solver
from vlab.scene.specimen import SCENE_DIR, SHAPES, parse_specimen
from vlab.scene.test import parse_test

if TYPE_CHECKING:
    from vlab.scene.material import MaterialSpec
    from vlab.scene.instruments import InstrumentsSpec
    from vlab.scene.measure import MeasureSpec
    from vlab.scene.mesh import MeshSpec
    from vlab.scene.solver import SolverSpec
    from vlab.scene.specimen import Specimen
    from vlab.scene.test import TestSpec

__all__ = ["Scene", "SECTIONS", "TOP_KEYS", "parse_scene", "load_scene", "load_scene_text"]


SECTIONS = ("specimen", "mesh", "material", "test", "measure", "solver", "effects", "compare", "instruments")


TOP_KEYS = ("name", "description") + SECTIONS + ("uncertainty",)  # [uncertainty]: `vlab budget` only


_NAME_RE = re.compile(r"[A-Za-z0-9._-]+")


@dataclass(frozen=True)
class Scene:
    name: str
    description: str
    specimen: Specimen
    mesh: MeshSpec
    material: MaterialSpec
    test: TestSpec
    measure: MeasureSpec
    solver: SolverSpec
    source: dict  # the raw parsed TOML, for provenance
    effects: tuple = ()  # validated effect specs (vlab.effects), each with a ``name``; () = elastic

    def effect(self, name: str):
        """The spec of the declared effect ``name``, or None."""
        return next((e for e in self.effects if e.name == name), None)
    base_dir: str = "."  # where relative paths in the scene (specimen.file) are taken from
    instruments: InstrumentsSpec | None = None  # [instruments] (vlab.scene.instruments); None: none declared

    def content_hash(self) -> str:
        """sha256 hex of the canonical JSON of ``source`` (sorted keys; key order irrelevant)."""
        text = json.dumps(self.source, sort_keys=True, separators=(",", ":"),
                          ensure_ascii=False, default=str)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _parse(data: Mapping[str, Any]) -> Scene:
    """The Scene of a scene file's tables, each section parsed by its module (vlab/scene/) and then
    the checks across sections; the first error is a SceneError naming the field."""
    name, description = _header(data)
    specimen = parse_specimen(data["specimen"])
    mesh, material = parse_mesh(data["mesh"], specimen), parse_material(data["material"])
    if specimen.shape == "cad":  # meshed by Gmsh now that mesh.size is known
        from vlab.geometry.cad_specimen import meshed

        specimen = meshed(specimen, mesh.size)
    check_formulation(mesh, material.model)
    parse_compare(data.get("compare", {}))  # every [compare.<label>] card, validated now
    _check_network(material.model, mesh, specimen)
    test = parse_test(data["test"], specimen.shape, specimen)
    _check_test(test, specimen, data.get("effects", {}))
    if continuum(material.model):  # a locking limit on the test's path (Gent)
        check_path(material, kind_of(test), test, specimen)
    check_symmetry(mesh, test, specimen)
    check_effects_scope(data.get("effects", {}), specimen.shape, mesh, material.model)
    scene = Scene(name=name, description=description, specimen=specimen,
                  mesh=mesh, material=material, test=test,
                  measure=parse_measure(data.get("measure", {}), specimen),
                  solver=parse_solver(data.get("solver", {})),
                  source=copy.deepcopy(dict(data)), base_dir=str(SCENE_DIR.get()),
                  effects=parse_effects(data.get("effects", {}), material, test),
                  instruments=parse_instruments(data.get("instruments"), specimen))
    if "uncertainty" in data:  # validated with the scene it perturbs (a run ignores it)
        from vlab.uncertainty.spec import parse_uncertainty

        parse_uncertainty(data["uncertainty"], scene)
    return scene


def _header(data: Any) -> tuple[str, str]:
    """(name, description) once the top level holds only known sections and keys and every
    required section."""
    if not isinstance(data, Mapping):
        raise SceneError(f"a scene must be a table of sections, got {fields.show(data)}")
    for key, val in data.items():
        if key not in TOP_KEYS:
            what = f"section [{key}]" if isinstance(val, dict) else f"top-level key {key!r}"
            raise SceneError(f"unknown {what} (allowed: {', '.join(TOP_KEYS)})"
                             f"{fields.suggest(key, TOP_KEYS)}")
    for section in ("specimen", "mesh", "material", "test"):
        if section not in data:
            raise SceneError(f"missing required section [{section}]")
    if "name" not in data:
        raise SceneError("missing required key name")
    name = data["name"]
    if not isinstance(name, str) or not _NAME_RE.fullmatch(name) or set(name) == {"."}:
        raise SceneError(f"name must match [A-Za-z0-9._-]+ (it names the report folder) and not "
                         f"be only dots, got {fields.show(name)}")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise SceneError(f"description must be a string, got {fields.show(description)}")
    return name, description


def _check_network(model: str, mesh, specimen) -> None:
    """A spring network (not a continuum) joins mesh vertices in 3D: order 1, no sheet."""
    if not continuum(model) and mesh.order != 1:
        raise SceneError(f"material.model {model!r} joins mesh vertices by springs and needs "
                         f"mesh.order = 1, got {mesh.order}")
    if not continuum(model) and specimen.shape == "sheet":
        raise SceneError(f"material.model {model!r} is a 3D network of mesh edges; "
                         f"specimen.shape = 'sheet' needs a continuum model (not {model!r})")


def _check_test(test: TestSpec, specimen: Specimen, effects: Any) -> None:
    """What the test kind refuses (vlab.loading.kinds: ``check``) and an imperfection on a shape
    without a cross-section thickness."""
    kind_of(test).check(test, effects if isinstance(effects, dict) else {})
    kind_of(test).check_specimen(test, specimen)
    if test.imperfection is not None and SHAPES[specimen.shape].thickness is None:
        raise SceneError(f"test.imperfection needs a specimen with a cross-section thickness (specimen.shape = "
                         f"{' or '.join(repr(n) for n, sh in SHAPES.items() if sh.thickness)}), "
                         f"got {specimen.shape!r}")


def parse_scene(data: dict, origin: str = "<scene>", base_dir: str | Path | None = None) -> Scene:
    """Validate a parsed scene dict; errors are ``SceneError("<origin>: <message>")``. Relative
    paths in the scene (specimen.file) are taken from ``base_dir`` (default: the current folder)."""
    # absolute: the scene may be run from another folder later (a Dask worker, a companion solve)
    token = SCENE_DIR.set(Path(base_dir if base_dir is not None else ".").resolve())
    try:
        return _parse(data)
    except SceneError as exc:
        raise SceneError(f"{origin}: {exc}") from None
    finally:
        SCENE_DIR.reset(token)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene TOML file; every error message starts with the file name."""
    return load_scene_text(path)[0]


def load_scene_text(path: str | Path) -> tuple[Scene, str]:
    """The validated scene and the text it was read from (read once, bounded: vlab.scene.file)."""
    from vlab.scene.file import parse_toml, read_scene_file

    path = Path(path)
    text = read_scene_file(path)
    data = parse_toml(text, str(path), "scene file")
    return parse_scene(data, origin=str(path), base_dir=path.parent), text
