"""Run one scene with several material models, each in its own process, and collect what the
reports need (results dict + snapshot) as plain picklable data.

The models are independent tests, so they run concurrently on the machine's cores. Worker
processes report each converged load level through a queue; the caller turns those events into
progress display (the library itself never prints).
"""

from __future__ import annotations

import copy
import logging
import multiprocessing as mp
import os
import queue as queue_module
from concurrent.futures import ProcessPoolExecutor, wait, FIRST_COMPLETED
from dataclasses import dataclass
from typing import Callable

import numpy as np

from vlab.loading.schedule import monotonic_schedule
from vlab.post.snapshot import Snapshot
from vlab.materials.registry import MODELS
from vlab.scene import Scene, SceneError, apply_overrides, parse_scene

log = logging.getLogger(__name__)

DEFAULT_MODELS = ("linear", "stvk", "neo-hookean")
REFERENCE_MODEL = "neo-hookean"  # the model the others are measured against

#: progress event: (model, levels done, levels scheduled); levels done == scheduled when finished
Progress = Callable[[str, int, int], None]


@dataclass(frozen=True)
class ModelOutcome:
    """One model's test: the results.json dict, the snapshot for renders/VTU, checks of the model."""

    model: str
    data: dict
    snapshot: Snapshot
    checks: dict
    critical_mode: object = None  # eigenvector of the first loss of stability (full DOF vector), if any


def compare_labels(scene: Scene) -> tuple[str, ...]:
    """The labels of the scene's ``[compare.<label>]`` material cards (may be empty)."""
    return tuple(scene.source.get("compare", {}))


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
    return len(monotonic_schedule(scene.test.stretch, scene.test.steps, scene.measure.modulus_window))


def _model_checks(result) -> dict:
    """Model-specific evidence shown in the report: a Taylor test for the spring network, whose
    force and stiffness have no analytic homogeneous oracle to be checked against."""
    if MODELS[result.scene.material.model].continuum:
        return {}
    from vlab.fe.taylor import random_state, taylor_test

    body = result.extra["body"]
    u, v = random_state(body, 0.02 * min(body.L))
    check = taylor_test(body, u, v, h0=0.05 * min(body.L)).as_dict()
    return {"taylor": check, "springs": body.n_springs, "stiffness_factor": 6.0}


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


def outcome_of(result, label: str | None = None) -> ModelOutcome:
    """Package a RunResult for the reports; ``label`` (default: the model name) names the
    outcome, its folder and its curves (results.json → input.label)."""
    from dataclasses import replace

    from vlab.post.snapshot import take_snapshot
    from vlab.report.results import result_to_dict

    label = label or result.scene.material.model
    data = result_to_dict(result)
    data["input"]["label"] = label
    critical = result.extra.get("critical_state")
    return ModelOutcome(label, data, replace(take_snapshot(result), model=label),
                        _model_checks(result), None if critical is None else critical.mode)


_events = None  # the worker's end of the progress queue (set by the pool initializer)


def _init_worker(events) -> None:
    global _events
    _events = events
    # the workers already share the cores: one assembly thread each
    os.environ["VLAB_ASSEMBLY_THREADS"] = "1"


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
    context = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
    events = context.Queue()
    with ProcessPoolExecutor(workers, mp_context=context, initializer=_init_worker,
                             initargs=(events,)) as pool:
        futures = {model: pool.submit(_worker, scene, model) for model in models}
        pending = set(futures.values())
        while pending:
            _, pending = wait(pending, timeout=0.1, return_when=FIRST_COMPLETED)
            _drain(events, progress)
        _drain(events, progress)
        return [futures[m].result() for m in models]


def _drain(events, progress: Progress | None) -> None:
    while True:
        try:
            model, done, total = events.get_nowait()
        except queue_module.Empty:
            return
        if progress is not None:
            progress(model, done, total)


def departure_strains(reference: dict, other: dict, thresholds=(0.05, 0.10)) -> dict[str, float | None]:
    """Extensometer strain at which ``other``'s engineering stress first differs from
    ``reference``'s by each relative threshold, |s − s_ref| / |s_ref|, compared level by level at
    the same grip stretch and interpolated linearly between levels; None if it never does."""
    s_ref, s = np.asarray(reference["curve"]["stress"]), np.asarray(other["curve"]["stress"])
    strain = np.asarray(other["curve"]["strain"])
    n = min(len(s_ref), len(s))
    rel = np.abs(s[:n] - s_ref[:n]) / np.maximum(np.abs(s_ref[:n]), 1e-300)
    out: dict[str, float | None] = {}
    for threshold in thresholds:
        above = np.flatnonzero(rel >= threshold)
        key = f"{round(threshold * 100):d}%"
        if len(above) == 0:
            out[key] = None
        elif above[0] == 0:
            out[key] = float(strain[0])
        else:
            i = above[0]
            w = (threshold - rel[i - 1]) / (rel[i] - rel[i - 1])
            out[key] = float(strain[i - 1] + w * (strain[i] - strain[i - 1]))
    return out
