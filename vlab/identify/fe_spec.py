"""The [fe] table of a fit file: the scene whose test is fitted to a specimen's readings.

    [fe]
    scene = "dogbone.toml"          # resolved against the fit file's folder; validated as a scene
    parameters = ["mu"]             # the material constants fitted (the others stay as the scene has them)
    start = { mu = 0.5 }            # optional start (default: the scene's values)
    max_solves = 15                 # whole-test solves allowed (1..200)
    cache = true                    # keep each solve's readings and sensitivities in reports/.cache
                                    # (false: none; or a folder), keyed like vlab's sweep cache

The scene's material model must be the fit file's [model] name. Fittable constants per model
(the FE library's grammar), those the stress is linear in, so that ∂P/∂p is exact:
neo-hookean: mu, K (the scene's other constant is converted to K); mooney-rivlin: C10, C01, K;
yeoh: C10, C20, C30, K (the card models of issue #18, once the FE library has them).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from vlab import fields
from vlab.fields import SceneError, Table

__all__ = ["parse_fe", "FITTABLE"]

FITTABLE = {"neo-hookean": ("mu", "K"), "mooney-rivlin": ("C10", "C01", "K"), "yeoh": ("C10", "C20", "C30", "K")}


def _scene(t: Table, base: Path):
    from vlab.scene import parse_scene

    name = t.get("scene")
    if not isinstance(name, str) or not name:
        raise SceneError(f"fe.scene must be a scene file name (string), got {fields.show(name)}")
    path = (base / name).resolve()
    if not path.is_file():
        raise SceneError(f"fe.scene: scene file {str(path)!r} does not exist")
    try:
        raw = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"fe.scene: {path.name} is not valid TOML: {exc}") from None
    return path, raw, parse_scene(raw, path.name, path.parent)


def parse_fe(raw, base: Path, model, datasets) -> dict:
    """The validated [fe] table as a dict (scene path, raw scene dict, parsed scene, parameters...)."""
    if raw is None:
        raise SceneError("a data set of kind = \"specimen\" needs an [fe] table with scene = \"<scene>.toml\"")
    t = Table("fe", raw, ("scene", "parameters", "start", "max_solves", "cache"))
    path, scene_raw, scene = _scene(t, base)
    name = scene.material.model
    if name != model.law.model:
        raise SceneError(f"fe.scene: the scene's material.model is {name!r} but model.name is "
                         f"{model.law.model!r}; they must be the same model")
    allowed = FITTABLE.get(name)
    if allowed is None:
        raise SceneError(f"fe.scene: FE-in-the-loop fits support material.model in {', '.join(FITTABLE)}, "
                         f"got {name!r}")
    if scene.mesh.formulation != "displacement" or scene.effects:
        raise SceneError("fe.scene: FE-in-the-loop fits need mesh.formulation = \"displacement\" and no [effects]")
    params = t.get("parameters", [allowed[0]])
    if not isinstance(params, list) or not params or len(set(params)) != len(params):
        raise SceneError(f"fe.parameters must be a non-empty list of distinct names from {', '.join(allowed)}, "
                         f"got {fields.show(params)}")
    for p in params:
        fields.choice("fe.parameters[]", p, allowed)
    moduli = scene.material.moduli
    values = {"K": moduli.lmbda + 2.0 * moduli.mu / 3.0}
    values |= {"mu": moduli.mu} if name == "neo-hookean" else dict(getattr(scene.material, "params", {}))
    start_raw = t.get("start", {})
    st = Table("fe.start", start_raw, tuple(params))
    start = {p: st.number(p, values[p], gt=0 if p in ("mu", "K", "C10") else None, note=" (MPa)")
             for p in params}
    specimen_sets = [d for d in datasets if d.kind == "specimen"]
    if any(d.b is not None for d in specimen_sets):
        raise SceneError("columns strain2/force2 (a cruciform's second axis) are not supported yet: fit one axis")
    if any(d.kind != "specimen" for d in datasets if d.role == "fit"):
        raise SceneError("an FE-in-the-loop fit takes only data sets of kind = \"specimen\"")
    return {"scene_path": str(path), "scene_raw": scene_raw, "scene": scene, "parameters": tuple(params),
            "model": name, "volumetric": getattr(scene.material, "volumetric", None),
            "start": start, "fixed": values, "max_solves": t.integer("max_solves", 1, 200, 15),
            "cache": _cache(t, base)}


def _cache(t: Table, base: Path) -> str | None:
    """fe.cache: true (vlab's run cache, reports/.cache under the working folder, as vlab run and
    sweep use), false, or a folder (resolved against the fit file's folder)."""
    from vlab.study.cache import DEFAULT_CACHE

    v = t.get("cache", True)
    if isinstance(v, bool):
        return str(DEFAULT_CACHE) if v else None
    if isinstance(v, str) and v:
        return str((base / v).resolve())
    raise SceneError(f"fe.cache must be true, false or a folder name, got {fields.show(v)}")
