"""``vlab.sweep`` and ``vlab.cost``: many runs of one scene on Dask, with the run cache in front, from
Python: the code of ``vlab sweep`` and ``vlab cost`` (vlab.study.commands, vlab.study.sweep), returning
what sweep.json and cost.json hold and their tables (sweep.csv, cost.csv) as pandas DataFrames."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Mapping, Sequence

from vlab.api_tables import Record, as_json, frame, loaded_scene

__all__ = ["CostStudy", "Sweep", "cost", "sweep"]

DEFAULT_CACHE = Path("reports") / ".cache"  # the command line's --cache


def grid_options(grid: Mapping[str, object] | Sequence[str]) -> list[str]:
    """``{"material.nu": [0.3, 0.45]}`` -> ``["material.nu=0.3,0.45"]`` (each value a TOML literal,
    as ``--set`` reads it); a list of such texts is kept as it is."""
    if isinstance(grid, str):
        return [grid]
    if not isinstance(grid, Mapping):
        return [str(g) for g in grid]
    out = []
    for key, values in grid.items():
        values = values if isinstance(values, (list, tuple)) else [values]
        out.append(f"{key}=" + ",".join(json.dumps(v) for v in values))
    return out


def _runs(points, knobs, cache, workers: int, scheduler: str | None):
    """The points' summaries (vlab.study.sweep.run_sweep) with the cache and Dask of the CLI."""
    from vlab.study.cache import SummaryCache, check_cache_folder
    from vlab.study.scheduler import parse_address
    from vlab.study.sweep import Execution, run_sweep

    if scheduler is not None:
        parse_address(scheduler)
    cache = check_cache_folder(Path(cache))
    return run_sweep(points, knobs, SummaryCache(cache), Execution(workers=workers, scheduler=scheduler))


def sweep(scene, grid: Mapping[str, object] | Sequence[str], cache: str | Path = DEFAULT_CACHE, workers: int = 2,
          scheduler: str | None = None) -> "Sweep":
    """Run ``scene`` (a path or a vlab.Scene) over the grid (``{"material.nu": [0.3, 0.45]}`` or
    ``["material.nu=0.3,0.45"]``; the Cartesian product, the last key fastest), as ``vlab sweep
    SCENE --set …``: cached runs are not recomputed. Bad input raises a ValueError
    (vlab.SceneError naming the key, a bad cache folder or scheduler address)."""
    from vlab.study.commands import grid_points, sweep_meta
    from vlab.study.summary import RunKnobs

    parsed, _, label = loaded_scene(scene)
    sets = grid_options(grid)
    points = grid_points(parsed, sets)
    outcome = _runs(points, RunKnobs(), cache, workers, scheduler)
    return Sweep(parsed, sweep_meta(label, sets, outcome), outcome.summaries)


class Sweep(Record):
    """sweep.json's fields: ``meta`` (scene, grid, cache hits, computed, Dask times) and ``runs``
    (every run's summary, grid order); ``headers``/``rows`` (sweep.csv), ``to_pandas()`` (that
    table: the grid keys, then status, E, ν, final force and stress, DOFs, timings, …),
    ``failed`` (runs that failed or are invalid) and ``write_report(folder)``."""

    _what = "sweep.json"

    def __init__(self, scene, meta: dict, summaries: list[dict]):
        from vlab.study.commands import sweep_record
        from vlab.study.table import table_rows

        self._scene, self._summaries = scene, summaries
        super().__init__(as_json(sweep_record(meta, summaries)))
        self.headers, self.rows = table_rows(self.data["runs"])

    @property
    def failed(self) -> int:
        return sum(r["status"] != "ok" for r in self.data["runs"])

    def to_pandas(self):
        return frame(rows=self.rows, headers=self.headers)

    def write_report(self, folder: str | Path, force: bool = False) -> Path:
        """The folder ``vlab sweep`` writes (sweep.csv, sweep.json, index.html); its index.html."""
        from vlab.report.folder import Destination, check_destination
        from vlab.study.table import write_sweep_report

        dest = check_destination(Destination(Path(folder), force=force, protect=(DEFAULT_CACHE,), option="folder"))
        return write_sweep_report(dest, f"{self._scene.name}: sweep", self._summaries, self.data["meta"])


def cost(scene, target: float = 0.01, levels: int = 4, ratio: float = math.sqrt(2.0), orders=(1, 2),
         cells=("tet", "hex"), cache: str | Path = DEFAULT_CACHE, workers: int = 2, scheduler: str | None = None,
         render: bool = False) -> "CostStudy":
    """What accuracy costs (``vlab cost SCENE``): the scene re-run over mesh size (``levels`` sizes,
    ``ratio`` apart, for each of ``orders`` and ``cells``), load steps, Newton tolerance and model;
    each run's error against the analytic or Richardson reference, the Pareto front and the
    cheapest run within ``target`` (relative). Bad input raises a ValueError naming the option."""
    from vlab.study.commands import cost_meta, cost_options
    from vlab.study.cost import analyse, knob_points
    from vlab.study.summary import RunKnobs

    parsed, _, label = loaded_scene(scene)
    options = cost_options(parsed, levels, ratio, target, tuple(orders), tuple(cells), flag="", origin=label)
    outcome = _runs(knob_points(parsed, options), RunKnobs(time_report=True, render=render), cache, workers,
                    scheduler)
    analysis = analyse(parsed, outcome.summaries, options)
    return CostStudy(parsed, cost_meta(label, parsed, options, outcome, render), analysis, outcome.summaries)


class CostStudy(Record):
    """cost.json's fields: ``meta``, ``reference_kind``, ``reference``, ``observed_order``,
    ``family_fits``, ``notes``, ``round_off``, ``pareto_front``, ``recommended`` (an index into
    ``runs``), ``recommendation``, ``errors``, ``runs``; ``headers``/``rows`` (cost.csv),
    ``to_pandas()`` and ``write_report(folder)``."""

    _what = "cost.json"

    def __init__(self, scene, meta: dict, analysis, summaries: list[dict]):
        from vlab.study.commands import cost_record, cost_table

        self._scene, self._analysis, self._summaries = scene, analysis, summaries
        super().__init__(as_json(cost_record(meta, analysis, summaries)))
        self.headers, self.rows = cost_table(self.data["runs"], analysis)

    def to_pandas(self):
        return frame(rows=self.rows, headers=self.headers)

    def write_report(self, folder: str | Path, force: bool = False) -> Path:
        """The folder ``vlab cost`` writes (error_time.png, cost.csv, cost.json, index.html)."""
        from vlab.report.folder import Destination, check_destination
        from vlab.study.cost_report import write_cost_report

        dest = check_destination(Destination(Path(folder), force=force, protect=(DEFAULT_CACHE,), option="folder"))
        return write_cost_report(dest, f"{self._scene.name}: what accuracy costs", self._summaries, self._analysis,
                                 self.data["meta"]["target"], self.data["meta"])
