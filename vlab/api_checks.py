"""``vlab.stability`` and ``vlab.export`` from Python: the stability suite's verdicts (the code of
``vlab stability``: vlab.verification.suite) and a material card's text for each solver (the code
of ``vlab export``: vlab.export.command)."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Sequence

from vlab.api_tables import Record, frame

__all__ = ["Export", "Stability", "export", "stability"]

CASE_COLUMNS = ("name", "expected", "got", "passed", "converged", "iterations", "cutbacks", "negative_eigenvalues",
                "seconds", "fast")


def stability(fast: bool = False, cases: Sequence[str] | None = None, render: bool = False,
              figures: str | Path | None = None) -> "Stability":
    """Run the stability suite (``vlab stability``): every case, the ``fast`` subset, or the
    ``cases`` named; ``render``: the critical modes' renders, written to ``figures`` (default: a
    temporary folder kept while the result lives). An unknown case raises vlab.SceneError naming
    the known ones."""
    from vlab.scene import SceneError
    from vlab.verification.suite import CaseContext, run_timed, select, suite_mode
    from vlab.report.stability_report import suite_dict

    try:
        chosen = select(fast_only=fast, names=list(cases) if cases else None)
    except KeyError as exc:
        raise SceneError(exc.args[0]) from None
    keep = tempfile.TemporaryDirectory(prefix="vlab-stability-") if figures is None else None
    folder = Path(keep.name if keep else figures)
    folder.mkdir(parents=True, exist_ok=True)
    results, total = run_timed(chosen, CaseContext(folder, render))
    return Stability(suite_dict(results, suite_mode(fast, cases), total), results, folder, keep)


class Stability(Record):
    """The suite's results.json fields (``vlab_version``, ``date``, ``mode``, ``total_seconds``,
    ``passed``, ``failed``, ``cases``), ``verdicts`` ({case: passed}), ``to_pandas()`` (the table
    ``vlab stability`` prints) and ``write_report(folder)``."""

    _what = "stability results.json"

    def __init__(self, data: dict, results: list, figures: Path, keep=None):
        super().__init__(data)
        self._results, self._figures, self._keep = results, figures, keep

    @property
    def verdicts(self) -> dict[str, bool]:
        return {c["name"]: c["passed"] for c in self.data["cases"]}

    def to_pandas(self):
        return frame(rows=[[c.get(k) for k in CASE_COLUMNS] for c in self.data["cases"]], headers=CASE_COLUMNS)

    def write_report(self, folder: str | Path, force: bool = False) -> Path:
        """The folder ``vlab stability`` writes (results.json, index.html, the mode renders)."""
        from vlab.report.folder import Destination, check_destination
        from vlab.report.stability_report import write_stability_report

        dest = check_destination(Destination(Path(folder), force=force, option="folder"))
        write_stability_report(self._results, dest, self.data["mode"], self.data["total_seconds"], self._figures)
        return dest.path / "index.html"


def export(source, to: str | Sequence[str], units: str = "mm", elastic_only: bool = False) -> "Export":
    """The material card of ``source`` (a vlab fit folder, its fit.json or card.toml, a scene
    TOML, or a vlab.fit result) for each solver of ``to`` (abaqus, calculix, ansys, lsdyna, febio,
    felupe), exactly in its convention, in ``units`` (mm or SI), as ``vlab export``. A solver that
    has no exact card for the model is refused (ValueError naming the solvers that have one)."""
    from vlab.export import card as cards
    from vlab.export.card import card_of_fit
    from vlab.export.command import export_texts, parse_targets

    solvers = parse_targets(to if isinstance(to, str) else ",".join(to))
    card = card_of_fit(source.data, f"fit {source.name}") if hasattr(source, "card_toml") else \
        cards.load_source(Path(source))
    return Export(export_texts(card, solvers, units, elastic_only))


class Export(Record):
    """The card text per solver (``export["abaqus"]``, ``export.data``: {solver: text}, the files
    ``vlab export`` writes) and ``write(out)``: each to its default file name (abaqus.inp,
    ansys.mac, …) in the folder ``out``."""

    _what = "card text per solver"

    def write(self, out: str | Path = ".", force: bool = False) -> dict[str, Path]:
        """Write each card whole into the folder ``out`` (never replacing a file vlab did not write
        unless ``force``); {solver: path}."""
        from vlab.export import EXPORTERS
        from vlab.export.command import write_file

        paths = {t: Path(out) / EXPORTERS[t].default_file for t in self.data}
        for t, text in self.data.items():
            write_file(paths[t], text, force)
        return paths
