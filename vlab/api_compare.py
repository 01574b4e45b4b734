"""``vlab.compare``: one scene run with several material models side by side, from Python: the
code of ``vlab compare`` (vlab.compare), returning comparison.json's departures and each model's
results.json as a vlab.Result."""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

from vlab.api_tables import Record, frame, loaded_scene

__all__ = ["Comparison", "compare"]


def compare(scene=None, models: str | Sequence[str] | None = None, workers: int | None = None) -> "Comparison":
    """Run ``scene`` (a path or a vlab.Scene; None: the built-in default scene) with each of
    ``models`` (registry names or the scene's ``[compare.<label>]`` labels; default: the scene's
    labels, else linear, stvk, neo-hookean), in ``workers`` processes (default: one per core), as
    ``vlab compare``. An unknown model raises vlab.SceneError naming it and the allowed ones."""
    from vlab.compare import chosen_models, compare_models

    if scene is None:
        from vlab.cli_io import default_scene_path

        scene = default_scene_path()
    parsed, text, _ = loaded_scene(scene)
    chosen = chosen_models(parsed, models, option="models")
    return Comparison(parsed, text, compare_models(parsed, chosen, workers))


class Comparison(Record):
    """comparison.json's computed fields (``models``, ``departures_from_neo_hookean``: the strain
    where each model's stress first departs from Neo-Hookean's), ``results`` (each model's
    vlab.Result: results.json as ``data``, ``curve``, ``E``, ``nu``), ``to_pandas()`` (one row per
    model: converged, the measured constants) and ``write_report(folder)``."""

    _what = "comparison.json"

    def __init__(self, scene, text: str | None, outcomes: list):
        from vlab.api import Result
        from vlab.report.writer import comparison_departures

        self._scene, self._text, self._outcomes = scene, text, outcomes
        self.results = {o.model: Result(None, o.data, None) for o in outcomes}
        super().__init__({"models": [o.model for o in outcomes],
                          "departures_from_neo_hookean": comparison_departures(outcomes)})

    def to_pandas(self):
        rows = [{"model": m, "converged": r.converged} | r.constants for m, r in self.results.items()]
        headers = list(dict.fromkeys(k for row in rows for k in row))
        return frame(rows=[[row.get(h) for h in headers] for row in rows], headers=headers)

    def write_report(self, folder: str | Path, render: bool = True, force: bool = False) -> Path:
        """The folder ``vlab compare`` writes (each model's files, the plots, renders, index.html)."""
        from vlab.report.folder import Destination, check_destination
        from vlab.report.writer import ReportOptions, write_report

        dest = check_destination(Destination(Path(folder), force=force, option="folder"))
        write_report(self._outcomes, dest, self._scene, self._text, ReportOptions(render=render))
        return dest.path / "index.html"
