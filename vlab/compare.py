"""Run one scene with several material models, each in its own process, and collect what the
reports need (results dict + snapshot) as plain picklable data.

The models are independent tests, so they run concurrently on the machine's cores. Worker
processes report each converged load level through a queue; the caller turns those events into
progress display (the library itself never prints).
"""

from __future__ import annotations

import copy
import dataclasses
import logging
import multiprocessing as mp
import os
import queue as queue_module
from concurrent.futures import ProcessPoolExecutor, wait, FIRST_COMPLETED
from typing import Callable

import vlab as _vlab
from vlab import settings
from vlab.materials.registry import MODELS
from vlab.measure.departure import REFERENCE_MODEL, departure_strains  # noqa: F401  (public here too)
from vlab.report.outcome import ModelOutcome, outcome_of
from vlab.scene import Scene, SceneError, apply_overrides, parse_scene

log = logging.getLogger(__name__)

DEFAULT_MODELS = ("linear", "stvk", "neo-hookean")

#: progress event: (model, levels done, levels scheduled); levels done == scheduled when finished
Progress = Callable[[str, int, int], None]


def compare_labels(scene: Scene) -> tuple[str, ...]:
    """The labels of the scene's ``[compare.<label>]`` material cards (may be empty)."""
    return tuple(scene.source.get("compare", {}))


def chosen_models(scene: Scene, models: str | tuple | list | None, option: str = "--models") -> tuple[str, ...]:
    """The models to run: registry model names and the scene's ``[compare.<label>]`` labels (a
    comma-separated text or a sequence); by default the scene's labels if it has any, else
    linear, stvk, neo-hookean. SceneError naming ``option`` for an unknown or empty list."""
    labels = compare_labels(scene)
    if models is None:
        return labels or DEFAULT_MODELS
    items = models.split(",") if isinstance(models, str) else [str(m) for m in models]
    chosen = tuple(dict.fromkeys(m.strip() for m in items if m.strip()))
    allowed = tuple(labels) + tuple(m for m in MODELS if m not in labels)
    bad = [m for m in chosen if m not in allowed]
    if not chosen or bad:
        raise SceneError(f"{option} {models!r}: unknown {', '.join(map(repr, bad)) or 'empty list'}; "
                         f"allowed: {', '.join(allowed)} (comma-separated; [compare.<label>] labels of the "
                         f"scene, or model names that take the scene's own constants)")
    return chosen


def scene_for_model(scene: Scene, model: str) -> Scene:
    """The scene with the material ``model`` names (validated like a scene file): a
    ``[compare.<label>]`` card replaces the whole [material] table (keeping its density unless
    the card gives one); a registry model name replaces ``material.model`` only, so the scene's
    own constants must fit that model's grammar (a card model needs a [compare] card)."""
    cards = scene.source.get("compare", {})
    if model in cards:
        source = copy.deepcopy(scene.source)
        card = dict(cards[model])
        if "density" in source["material"] and "density" not in card:
            card["density"] = source["material"]["density"]
        source["material"] = card
        return parse_scene(source, origin=f"compare.{model}", base_dir=scene.base_dir)
    if model in MODELS and MODELS[model].constants is not None and scene.material.model != model:
        raise SceneError(f"--models {model}: material.model {model!r} takes its own constants "
                         f"({', '.join(MODELS[model].keys)} and K | D1 | nu); give them in a "
                         f"[compare.<label>] table with model = {model!r} and name the label")
    return parse_scene(apply_overrides(scene.source, {"material.model": model}), origin=f"model {model}",
                       base_dir=scene.base_dir)


def scheduled_levels(scene: Scene) -> int:
    """The levels the scene runs at (its protocol's and its kind's: vlab.loading.kinds.run_levels)."""
    from vlab.loading.kinds import run_levels

    return len(run_levels(scene))


def run_model(scene: Scene, model: str, on_level: Callable[[int], None] | None = None) -> ModelOutcome:
    """Run ``scene`` with ``model`` in this process."""
    from vlab.run import run_scene

    scene = scene_for_model(scene, model)
    count = [0]

    def observe(level):
        count[0] += 1
        if on_level is not None:
            on_level(count[0])

    return outcome_of(run_scene(scene, on_level=observe), label=model)


_events = None  # the worker's end of the progress queue (set by the pool initializer)


def _init_worker(events, parent: settings.Settings) -> None:
    global _events
    _events = events
    # the parent's settings (also under spawn); the workers already share the cores: one
    # assembly thread each
    settings.use(dataclasses.replace(parent, assembly_threads=1))


def _worker(scene: Scene, model: str) -> ModelOutcome:
    total = scheduled_levels(scene)
    return run_model(scene, model, lambda done: _events.put((model, done, total)))


def compare_models(scene: Scene, models: tuple[str, ...], workers: int | None = None,
                   progress: Progress | None = None) -> list[ModelOutcome]:
    """Run every model on ``scene`` (concurrently when more than one worker); outcomes in ``models`` order."""
    for model in models:
        scene_for_model(scene, model)  # bad model names fail here, before any process starts
    total = scheduled_levels(scene)
    workers = max(1, min(len(models), workers or os.cpu_count() or 1))
    if workers == 1:
        outcomes = []
        for model in models:
            report = (lambda done, m=model: progress(m, done, total)) if progress else None
            outcomes.append(run_model(scene, model, report))
        return outcomes
    context = _worker_context()
    events = context.Queue()
    with ProcessPoolExecutor(workers, mp_context=context, initializer=_init_worker,
                             initargs=(events, settings.current())) as pool:
        futures = {model: pool.submit(_worker, scene, model) for model in models}
        pending = set(futures.values())
        while pending:
            _, pending = wait(pending, timeout=0.1, return_when=FIRST_COMPLETED)
            _drain(events, progress)
        _drain(events, progress)
        return [futures[m].result() for m in models]


def _worker_context():
    """Workers start from a fork server, a fresh interpreter that has only imported vlab: a plain
    fork of a parent that has already run MKL PARDISO (or Gmsh) hands the child GNU OpenMP's
    thread pool in a locked state, and the child hangs in its first parallel factorization."""
    if "forkserver" not in mp.get_all_start_methods():
        return mp.get_context("spawn")
    context = mp.get_context("forkserver")
    context.set_forkserver_preload(["vlab.compare", "vlab.run"])  # import once in the server, not per worker
    return context


def _drain(events, progress: Progress | None) -> None:
    while True:
        try:
            model, done, total = events.get_nowait()
        except queue_module.Empty:
            return
        if progress is not None:
            progress(model, done, total)

_vlab._command_module(__name__)  # vlab.compare(...) is the Python API's command (vlab/__init__.py)
