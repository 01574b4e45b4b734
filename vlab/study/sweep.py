"""Run many independent scenes on Dask distributed, with the content-hash cache in front.

Each point is looked up in the cache first (key: scene content hash + vlab version + RunKnobs);
only misses are submitted, as ``summarize`` tasks, to a Dask cluster: a ``LocalCluster`` of worker
processes with one thread each (the FE code is single-threaded numpy/scipy work, so processes give
real parallelism), or an existing scheduler's address. A summary is written to the cache by the
client as soon as its task completes, so an interrupted sweep keeps every finished run and a rerun
submits only the rest. Failed or invalid points are summaries like any other (cached too: they are
deterministic); only unexpected errors ("error") are left out of the cache.
"""

from __future__ import annotations

import hashlib
import json
import logging
import time
from dataclasses import dataclass, field
from typing import Callable

from vlab.scene import SceneError, parse_scene
from vlab.study.cache import SummaryCache, cache_key, file_digest, referenced_files
from vlab.study.grid import GridPoint
from vlab.study.summary import RunKnobs, summarize

log = logging.getLogger(__name__)

#: progress(done, running, failed, total): done counts cache hits and failures too
SweepProgress = Callable[[int, int, int, int], None]
POLL_S = 0.25


@dataclass(frozen=True)
class Execution:
    """Where the runs execute: a new LocalCluster of ``workers`` processes, or ``scheduler``."""

    workers: int = 2
    scheduler: str | None = None  # e.g. "tcp://127.0.0.1:8786"


@dataclass
class SweepOutcome:
    summaries: list[dict]  # in the order of the points; each has "cache_hit"
    cache_hits: int = 0
    computed: int = 0
    seconds: dict = field(default_factory=dict)  # cluster start-up, compute, per-run overhead

    @property
    def failed(self) -> int:
        return sum(s["status"] != "ok" for s in self.summaries)


def point_key(point: GridPoint, knobs: RunKnobs) -> str:
    """Cache key of a point (vlab.study.cache): its scene's content hash (an unparseable scene is
    keyed by its raw dict), the bytes of every file it references, vlab's version and the knobs."""
    try:
        scene_hash = parse_scene(point.source, base_dir=point.base_dir).content_hash()
    except SceneError:
        raw = json.dumps(point.source, sort_keys=True, default=str).encode("utf-8")
        scene_hash = "raw:" + hashlib.sha256(raw).hexdigest()
    files = {k: file_digest(p) for k, p in referenced_files(point.source, point.base_dir).items()}
    return cache_key(scene_hash, knobs.as_dict(), files=files)


def run_sweep(points: list[GridPoint], knobs: RunKnobs, cache: SummaryCache,
              execution: Execution = Execution(), progress: SweepProgress | None = None) -> SweepOutcome:
    """Summaries of every point, computing only the ones not in ``cache``."""
    keys = [point_key(p, knobs) for p in points]
    summaries: list[dict | None] = [None] * len(points)
    for i, key in enumerate(keys):
        hit = cache.get(key)
        if hit is not None:
            summaries[i] = hit | {"cache_hit": True, "label": points[i].label}
    outcome = SweepOutcome([], cache_hits=sum(s is not None for s in summaries))
    missing = [i for i, s in enumerate(summaries) if s is None]
    # points with one key are one run (a cost study's knobs meet at the base scene): computed once,
    # so every copy carries the same summary, as it would from the cache
    first = {}
    for i in missing:
        first.setdefault(keys[i], i)
    unique = sorted(first.values())
    report = _Reporter(progress, len(points), summaries)
    report(0)
    if unique:
        _compute(points, keys, unique, knobs, cache, execution, summaries, report, outcome)
    for i in missing:
        if summaries[i] is None:
            summaries[i] = summaries[first[keys[i]]] | {"label": points[i].label}
    outcome.summaries = summaries  # type: ignore[assignment]
    outcome.computed = len(unique)
    return outcome


class _Reporter:
    def __init__(self, progress, total, summaries):
        self.progress, self.total, self.summaries = progress, total, summaries

    def __call__(self, running: int) -> None:
        if self.progress is None:
            return
        done = [s for s in self.summaries if s is not None]
        self.progress(len(done), running, sum(s["status"] != "ok" for s in done), self.total)


def _compute(points, keys, missing, knobs, cache, execution, summaries, report, outcome) -> None:
    from distributed import wait

    start = time.perf_counter()
    with _client(execution) as client:
        ready = time.perf_counter()
        futures = {client.submit(summarize, points[i].source, knobs, points[i].label, points[i].base_dir,
                                 key=f"vlab-run-{keys[i][:16]}-{i}", pure=False): i for i in missing}
        pending = set(futures)
        threads = _threads(client)
        while pending:
            try:
                done, pending = wait(pending, timeout=POLL_S, return_when="FIRST_COMPLETED")
            except TimeoutError:
                done = set()
            for future in done:
                i = futures[future]
                summaries[i] = _collect(future, points[i]) | {"cache_hit": False}
                if summaries[i]["status"] != "error":
                    cache.put(keys[i], {k: v for k, v in summaries[i].items() if k != "cache_hit"})
            report(min(threads, _running(client, pending)))
        workers = threads
    end = time.perf_counter()
    work = sum((summaries[i].get("timing") or {}).get("wall_s") or 0.0 for i in missing)
    outcome.seconds = {"cluster_start_s": ready - start, "compute_s": end - ready, "threads": workers,
                       "overhead_per_run_s": max(0.0, (end - ready) * workers - work) / len(missing)}


def _collect(future, point: GridPoint) -> dict:
    """The task's summary; a task that died (e.g. a worker killed) is an "error" row."""
    try:
        return future.result()
    except Exception as exc:  # noqa: BLE001 - one lost task must not abort the sweep
        return {"label": point.label, "status": "error", "diagnosis": f"{type(exc).__name__}: {exc}"}


def _threads(client) -> int:
    return max(1, sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values()))


def _running(client, pending) -> int:
    """Tasks of ``pending`` assigned to a worker (capped by the caller at the worker threads)."""
    try:
        processing = client.processing()
    except Exception:  # noqa: BLE001 - the count is cosmetic
        return 0
    ours = {f.key for f in pending}
    return sum(1 for tasks in processing.values() for key in tasks if key in ours)


class _client:
    """A distributed Client on a new LocalCluster (closed on exit) or on a given scheduler."""

    def __init__(self, execution: Execution):
        self.execution = execution
        self.cluster = None

    def __enter__(self):
        from distributed import Client, LocalCluster

        if self.execution.scheduler:
            from vlab.study.scheduler import connect

            self.client = connect(self.execution.scheduler)  # SchedulerError if it is none
            return self.client
        self.cluster = LocalCluster(n_workers=self.execution.workers, threads_per_worker=1, processes=True,
                                    dashboard_address=":0", scheduler_port=0, silence_logs=logging.ERROR)
        self.client = Client(self.cluster)
        return self.client

    def __exit__(self, *exc):
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()
        return False


cluster_client = _client  # the same cluster set-up for vlab.identify.fe_dask (FE-in-the-loop fits)
