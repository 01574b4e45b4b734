"""The coarse budget of a scene file: the overrides with which the test suite
(tests/test_specimen_files.py) and the documentation's gallery (docs/examples/) run every file in
``specimens/`` in seconds. ``vlab run FILE`` runs the file as written; this budget is for the
suite and the gallery only.

The budget: at most four load steps, and an element size h' of up to twice the file's own h,
never so coarse that fewer than two elements span the specimen's narrowest width w:

    h' = max(h, min(2 h, w / 2))        [mm]

A file with a ``gauge_size`` (a finer gauge section) or a mesh that vlab does not make (an imported
mesh, a CAD drawing meshed at the file's own size) keeps its mesh and loses only steps.
"""

from __future__ import annotations

from pathlib import Path

from vlab.fields import SceneError

__all__ = ["coarse_overrides", "NARROW_WIDTH"]

MAX_STEPS = 4

# the narrowest width w (mm) across which two elements must stay, per specimen shape
NARROW_WIDTH = {
    "dogbone": lambda spec: spec.dimensions.width,
    "block": lambda spec: min(spec.size[1:]),
    "sheet": lambda spec: spec.size[1],
    "cruciform": lambda spec: spec.dimensions.gauge_region / 2,
    "planar-tension": lambda spec: spec.thickness,
    "shear": lambda spec: spec.gap,
    "double-lap": lambda spec: spec.gap,
    "cylinder": lambda spec: spec.radius,
    "sphere-shell": lambda spec: spec.thickness,
    "membrane": lambda spec: spec.radius / 4,  # in-plane: the clamped disc, a quarter of its rim radius
}


def coarse_overrides(raw: dict, base_dir: Path) -> dict:
    """The dotted-key overrides (``{"test.steps": …, "mesh.size": …}``) that run the raw scene
    dict on the coarse budget (module docstring); ``base_dir`` resolves the scene's relative
    paths. A shape without a narrowest width here raises a SceneError naming ``specimen.shape``."""
    from vlab.scene.load import parse_scene

    spec = parse_scene(raw, base_dir=base_dir).specimen
    overrides: dict = {"test.steps": min(raw["test"].get("steps", 10), MAX_STEPS)}
    if spec.shape in ("mesh", "cad") or "gauge_size" in raw["mesh"]:
        return overrides
    if spec.shape not in NARROW_WIDTH:
        raise SceneError(f"specimen.shape: {spec.shape!r} has no coarse budget; add its narrowest width to "
                         f"vlab.scene.coarse.NARROW_WIDTH (has: {', '.join(sorted(NARROW_WIDTH))})")
    size = raw["mesh"]["size"]
    overrides["mesh.size"] = max(size, min(2 * size, NARROW_WIDTH[spec.shape](spec) / 2))
    return overrides
