"""What ``vlab sweep`` / ``vlab cost`` and ``vlab.sweep`` / ``vlab.cost`` share: the grid and the
study's options checked before any run (SceneError naming the option and its allowed range), and
the records the commands write (sweep.json, cost.json, the tables of sweep.csv and cost.csv).
Nothing here prints; the runs themselves are vlab.study.sweep.run_sweep."""

from __future__ import annotations

from vlab.scene import Scene, SceneError
from vlab.study.cost import GMSH_TET, CostAnalysis, CostOptions, fixed_mesh_note
from vlab.study.grid import GridPoint, expand_grid, parse_axis
from vlab.study.sweep import SweepOutcome
from vlab.study.table import table_rows

ORDERS, CELLS = (1, 2), ("tet", "hex", GMSH_TET)
#: cost.csv's error columns before the sweep's (header, path into the run's row)
ERROR_COLUMNS = (("rel. error E", ("errors", "E")), ("rel. error ν", ("errors", "nu")),
                 ("rel. error final force", ("errors", "final_force")),
                 ("rel. error final stress", ("errors", "final_stress")), ("largest error", ("errors", "max")))
LEVELS_MIN, RATIO_RANGE = 3, (1.1, 4.0)  # Richardson needs three sizes; the ratio as --ratio allows


def grid_points(scene: Scene, sets: list[str]) -> list[GridPoint]:
    """One point per combination of the ``--set section.key=v1,v2`` axes (SceneError if malformed)."""
    return expand_grid(scene.source, [parse_axis(s) for s in sets], scene.base_dir)


def sweep_meta(scene: str, sets: list[str], outcome: SweepOutcome) -> dict:
    """sweep.json's "meta": the scene, the grid as given, cache hits, computed runs, Dask times."""
    return {"scene": scene, "grid": list(sets), "cache_hits": outcome.cache_hits, "computed": outcome.computed,
            "seconds": outcome.seconds}


def sweep_record(meta: dict, summaries: list[dict]) -> dict:
    """sweep.json: the meta and every run's summary (in the grid's order)."""
    return {"meta": meta, "runs": summaries}


def cost_options(scene: Scene, levels: int, ratio: float, target: float, orders, cells,
                 flag: str = "--", origin: str = "the scene") -> CostOptions:
    """The study's CostOptions, each checked: ``levels`` ≥ 3, ``ratio`` in [1.1, 4], ``target`` in
    (0, 1), ``orders`` ⊆ {1, 2}, ``cells`` ⊆ {tet, hex, gmsh-tet} (gmsh-tet: a dogbone only);
    errors name the option as ``flag + name`` (the CLI's --target, the API's target) and the scene
    as ``origin``."""
    if not (isinstance(levels, int) and levels >= LEVELS_MIN):
        raise SceneError(f"{flag}levels {levels!r}: an integer ≥ {LEVELS_MIN}")
    if not RATIO_RANGE[0] <= float(ratio) <= RATIO_RANGE[1]:
        raise SceneError(f"{flag}ratio {ratio!r}: between {RATIO_RANGE[0]} and {RATIO_RANGE[1]}")
    if not 0.0 < float(target) < 1.0:
        raise SceneError(f"{flag}target {target!r}: a relative accuracy in (0, 1), e.g. 1% or 0.01")
    options = CostOptions(levels=levels, ratio=float(ratio), target=float(target),
                          orders=_subset(f"{flag}orders", orders, ORDERS), cells=_subset(f"{flag}cells", cells, CELLS))
    if GMSH_TET in options.cells and scene.specimen.shape != "dogbone":
        raise SceneError(f"{flag}cells gmsh-tet meshes a dogbone; {origin} has specimen.shape = "
                         f"{scene.specimen.shape!r}")
    return options


def _subset(option: str, values, allowed: tuple) -> tuple:
    chosen = tuple(dict.fromkeys(values))
    if not chosen or any(v not in allowed for v in chosen):
        raise SceneError(f"{option} {','.join(map(str, values))!r}: a comma-separated subset of "
                         f"{','.join(map(str, allowed))}")
    return chosen


def cost_meta(scene_label: str, scene: Scene, options: CostOptions, outcome: SweepOutcome, render: bool) -> dict:
    """cost.json's "meta": the options, cache hits, computed runs, Dask times, the memory method."""
    memory = next((s["memory"]["method"] for s in outcome.summaries if s.get("memory")), "")
    return {"scene": scene_label, "target": options.target, "levels": options.levels, "ratio": options.ratio,
            "orders": list(options.orders), "cells": list(options.cells), "cache_hits": outcome.cache_hits,
            "computed": outcome.computed, "seconds": outcome.seconds, "render": render, "memory_method": memory,
            "fixed_mesh": fixed_mesh_note(scene)}


def cost_record(meta: dict, analysis: CostAnalysis, summaries: list[dict]) -> dict:
    """cost.json: the meta, the reference and its observed orders, the errors of every run, the
    Pareto front, the recommended run (an index into ``runs``) and its recommendation in words."""
    return {"meta": meta, "reference_kind": analysis.reference_kind, "reference": analysis.reference,
            "observed_order": analysis.orders, "family_fits": analysis.fits, "notes": analysis.notes,
            "round_off": analysis.round_off, "pareto_front": analysis.front, "recommended": analysis.best,
            "recommendation": analysis.recommendation, "errors": analysis.errors, "runs": summaries}


def cost_table(summaries: list[dict], analysis: CostAnalysis) -> tuple[list[str], list[list]]:
    """cost.csv's headers and rows: the knob and its value, the errors, then the sweep's columns."""
    return table_rows([s | {"errors": e or {}} for s, e in zip(summaries, analysis.errors)], extra=ERROR_COLUMNS)
