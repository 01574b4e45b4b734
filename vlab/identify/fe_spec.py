"""The [fe] table of a fit file: the scene whose test is fitted to a specimen's readings.

    [fe]
    scene = "dogbone.toml"          # resolved against the fit file's folder; validated as a scene
    parameters = ["mu"]             # the material constants fitted (the others stay as the scene has them)
    start = { mu = 0.5 }            # optional start (default: the scene's values)
    max_solves = 15                 # whole-test solves allowed (1..200)
    cache = true                    # keep each solve's readings and sensitivities in reports/.cache
                                    # (false: none; or a folder), keyed like vlab's sweep cache

The scene's material model must be the fit file's [model] name; every model of the library can be
fitted (vlab.identify.fe_stress gives ∂P/∂p of each). Fittable constants, by their card keys:
neo-hookean mu, K (the scene's other constant is converted to K); mooney-rivlin C10, C01, K;
yeoh C10, C20, C30, K; gent mu, Jm, K; arruda-boyce mu, lambda_m, K; ogden "mu[p]", "alpha[p]"
(one per term; "mu" or "alpha" alone: every term), K. ``start`` takes the same names (quoted:
"alpha[1]" = 2.5) or a card list (mu = [..]). The scene's test.kind is one of
vlab.identify.fe_readings.SPECIMEN_KINDS, whose entry says what the data's columns are (an extension
test: strain, force; a cruciform also strain2, force2; torsion: twist, torque and axial_force or a
free end's axial_stretch; inflation: stretch, volume_ratio or pole_height, and pressure; confined
compression: stretch, stress); every specimen data set gives the same channels (fe["channels"]).
"""

from __future__ import annotations

from pathlib import Path

from vlab import fields
from vlab.fields import SceneError, Table
from vlab.identify.fe_readings import SPECIMEN_KINDS
from vlab.materials.arruda_boyce import LAMBDA_M_MAX
from vlab.materials.ogden import ALPHA_RANGE

__all__ = ["parse_fe", "specimen_scene", "FITTABLE_MODELS", "fittable", "admissible", "load_scene", "check_scene"]

FITTABLE_MODELS = ("neo-hookean", "mooney-rivlin", "yeoh", "gent", "arruda-boyce", "ogden")
FE_KINDS = tuple(SPECIMEN_KINDS)
SIGN_FREE = ("C01", "C20", "C30")  # may take either sign; every other constant keeps its own


def _scene(t: Table, base: Path):
    name = t.get("scene")
    if not isinstance(name, str) or not name:
        raise SceneError(f"fe.scene must be a scene file name (string), got {fields.show(name)}")
    return load_scene((base / name).resolve(), "fe.scene")


def load_scene(path: Path, label: str):
    """(path, raw dict, parsed scene) of a scene file; SceneError prefixed with ``label``."""
    from vlab.scene import parse_scene
    from vlab.scene.file import parse_toml, read_scene_file

    try:
        raw = parse_toml(read_scene_file(path), path.name, "scene file")
    except SceneError as exc:
        raise SceneError(f"{label}: {exc}") from None
    return path, raw, parse_scene(raw, path.name, path.parent)


def check_scene(scene, model_name: str, label: str) -> None:
    """A scene vlab can run in the loop: the fit's material model (one of FITTABLE_MODELS), the
    displacement formulation, no [effects], and what the test kind's entry checks (test.kind in
    FE_KINDS: specimen_scene)."""
    name = scene.material.model
    if name != model_name:
        raise SceneError(f"{label}: the scene's material.model is {name!r} but model.name is "
                         f"{model_name!r}; they must be the same model")
    if name not in FITTABLE_MODELS:
        raise SceneError(f"{label}: FE-in-the-loop fits support material.model in {', '.join(FITTABLE_MODELS)}, "
                         f"got {name!r}")
    if scene.mesh.formulation != "displacement" or scene.effects:
        raise SceneError(f"{label}: FE-in-the-loop fits need mesh.formulation = \"displacement\" and no [effects]")
    _check_kind(scene.test.kind, label)
    SPECIMEN_KINDS[scene.test.kind].check(scene)


def fittable(values: dict) -> tuple[str, ...]:
    """The flat names a fit may adjust: every constant of the scene's card (K last)."""
    return tuple(n for n in values if n != "K") + ("K",)


def admissible(names, p, reference=None) -> bool:
    """A trial point keeps 1 < λm <= LAMBDA_M_MAX, K, mu, C10, Jm > 0 and each Ogden term's signs
    (those of ``reference``) with |α| in ALPHA_RANGE (a card the scene reads); C01, C20 and C30 may
    take either sign."""
    for n, v, r in zip(names, p, p if reference is None else reference):
        if n == "lambda_m":
            ok = 1.0 < v <= LAMBDA_M_MAX
        elif n in SIGN_FREE:
            ok = True
        elif n.startswith(("alpha[", "mu[")):
            ok = v != 0 and (v > 0) == (r > 0) and (n[0] == "m" or ALPHA_RANGE[0] <= abs(v) <= ALPHA_RANGE[1])
        else:
            ok = v > 0
        if not ok:
            return False
    return True


def _parameters(t: Table, values: dict) -> tuple[str, ...]:
    allowed = fittable(values)
    params = t.get("parameters", [allowed[0]])
    if not isinstance(params, list) or not params:
        raise SceneError(f"fe.parameters must be a non-empty list of names from {', '.join(allowed)}, "
                         f"got {fields.show(params)}")
    out = []
    for p in params:
        expand = [n for n in allowed if isinstance(p, str) and n.startswith(p + "[")]
        out += expand or [fields.choice("fe.parameters[]", p, allowed)]
    if len(set(out)) != len(out):
        raise SceneError(f"fe.parameters names a constant twice: {fields.show(params)}")
    return tuple(out)


def _start(raw, params, values: dict) -> dict:
    t = Table("fe.start", raw, tuple(params) + tuple({n.split("[")[0] for n in params if "[" in n}))
    start = {}
    for key, v in t.raw.items():
        if isinstance(v, list):
            names = [n for n in params if n.startswith(key + "[")]
            if len(v) != len(names):
                raise SceneError(f"fe.start.{key} must list {len(names)} values (one per term), got {len(v)}")
            start |= {n: fields.number(f"fe.start.{key}[]", x) for n, x in zip(names, v)}
        else:
            start[key] = t.number(key, None, note=" (the constant's unit)")
    out = {p: float(start.get(p, values[p])) for p in params}
    if not admissible(params, [out[p] for p in params], [values[p] for p in params]):
        raise SceneError(f"fe.start: {out} is not admissible (K, mu, C10, Jm > 0; lambda_m > 1; "
                         "Ogden terms keep the scene's signs)")
    return out


def _check_data_kinds(datasets, scene) -> None:
    """Only specimen data sets, or only DIC fields (kind = "field", on an unreduced mesh)."""
    kinds = {d.kind for d in datasets if d.role == "fit"}
    if kinds not in ({"specimen"}, {"field"}):
        raise SceneError("an FE-in-the-loop fit takes only data sets of kind = \"specimen\", or only of kind = "
                         f"\"field\" (DIC fields, vlab.identify.field_fit), got {', '.join(sorted(kinds))}")
    if kinds == {"field"} and scene.mesh.symmetry != "none":
        raise SceneError(f"fe.scene: a field fit needs mesh.symmetry = \"none\" (the camera sees the whole face), "
                         f"got {scene.mesh.symmetry!r}")


def _channels(datasets) -> tuple[tuple[str, str], ...]:
    """The (control, reading) column keys every specimen data set gives (the same in each); DIC
    fields (kind = "field"): the extensometer and the x load cell."""
    sets = [d for d in datasets if d.kind == "specimen"]
    if not sets:
        return (("strain", "force"),)
    channels = {tuple(d.extra["channels"]) for d in sets}
    if len(channels) > 1:
        a, b = sorted(channels, key=len)[:2]
        raise SceneError(f"the specimen data sets give different columns ({_show(a)} and {_show(b)}): give the "
                         "same readings in every specimen data set (the fit matches one simulated test)")
    return next(iter(channels))


def _show(channels) -> str:
    return ", ".join(f"{r} against {c}" for c, r in channels)


def specimen_scene(raw, base: Path):
    """(the [fe] Table, (path, raw dict, parsed scene)) of the fit's [fe] table, its test.kind one
    of FE_KINDS (read before the specimen data sets: their columns are the kind's)."""
    if raw is None:
        raise SceneError("a data set of kind = \"specimen\" or \"field\" needs an [fe] table with scene = "
                         "\"<scene>.toml\"")
    t = Table("fe", raw, ("scene", "parameters", "start", "max_solves", "cache"))
    loaded = _scene(t, base)
    _check_kind(loaded[2].test.kind, "fe.scene")
    return t, loaded


def _check_kind(kind: str, label: str) -> None:
    if kind not in FE_KINDS:
        raise SceneError(f"{label}: test.kind must be one of {', '.join(FE_KINDS)} for an FE-in-the-loop fit, "
                         f"got {kind!r}")


def parse_fe(raw, base: Path, model, datasets) -> dict:
    """The validated [fe] table as a dict (scene path, raw scene dict, parsed scene, parameters...)."""
    from vlab.identify.fe_stress import flat_constants

    t, (path, scene_raw, scene) = specimen_scene(raw, base)
    name = scene.material.model
    check_scene(scene, model.law.model, "fe.scene")
    _check_data_kinds(datasets, scene)
    values = flat_constants(scene.material)
    params = _parameters(t, values)
    return {"scene_path": str(path), "scene_raw": scene_raw, "scene": scene, "parameters": params,
            "model": name, "volumetric": getattr(scene.material, "volumetric", None),
            "start": _start(t.get("start", {}), params, values), "fixed": values,
            "channels": (ch := _channels(datasets)),  # a field fit: the load cell (and its strain control)
            "axes": tuple(sorted({SPECIMEN_KINDS[scene.test.kind].quantity(r, scene).axis for _, r in ch})),
            "max_solves": t.integer("max_solves", 1, 200, 15),
            "cache": _cache(t, base)}


def _cache(t: Table, base: Path) -> str | None:
    """fe.cache: true (vlab's run cache, reports/.cache under the working folder, as vlab run and
    sweep use), false, or a folder (resolved against the fit file's folder)."""
    from vlab.study.cache import DEFAULT_CACHE, CacheError, check_cache_folder

    v = t.get("cache", True)
    if isinstance(v, bool):
        return str(DEFAULT_CACHE) if v else None
    if isinstance(v, str) and v:
        try:  # a file here was silently ignored (nothing cached): refused as vlab sweep --cache FILE is
            return str(check_cache_folder((base / v).resolve(), "fe.cache"))
        except CacheError as exc:
            raise SceneError(str(exc)) from None
    raise SceneError(f"fe.cache must be true, false or a folder name, got {fields.show(v)}")
