"""``vlab.fit``: a material card fitted to measured curves, from Python: the code of ``vlab fit``
(vlab.identify.request), without the terminal and without writing a folder until asked (docs/reference/python-api.md).
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

from vlab.api_tables import Record, frame

__all__ = ["Fit", "Ranking", "fit"]


def fit(fitfile: str | Path, models: str | Sequence[str] | None = None, workers: int | None = None,
        scheduler: str | None = None) -> "Fit | Ranking":
    """Fit the fit file's [model] to its data sets (``vlab fit FILE``) and return a :class:`Fit`
    (fit.json's fields); with ``models`` (names like ``"ogden-3"``, a list or a comma-separated
    text) fit each and rank them (``vlab fit FILE --models …``): a :class:`Ranking`. ``workers`` or
    ``scheduler`` (tcp://HOST:PORT) run an FE-in-the-loop fit's solves on Dask. Bad input raises
    vlab.SceneError naming the file, field or model."""
    from vlab.identify.request import fit_request, run_ranking, run_single
    from vlab.study.scheduler import parse_address
    from vlab.study.sweep import Execution

    if scheduler is not None:
        parse_address(scheduler)
    execution = Execution(workers or 1, scheduler) if workers or scheduler else None
    request = fit_request(Path(fitfile), models, distributed=execution is not None)
    if request.names:
        return Ranking(request, run_ranking(request))
    return Fit(run_single(request, execution), request)


class Fit(Record):
    """One fitted card: fit.json's fields (``name``, ``converged``, ``model``, ``parameters``,
    ``uncertainty``, ``datasets``, ``stability``, ``card``, ``trust``, …; ``files`` once written),
    ``card_toml`` (the [material] card), ``to_pandas()`` (the data against the fit) and
    ``write_report(folder)`` (the folder ``vlab fit`` writes)."""

    _what = "fit.json"

    def __init__(self, outcome, request):
        from vlab.identify.report import strict

        outcome.data = strict(outcome.data)  # as fit.json holds it: no NaN, lists not arrays
        super().__init__(outcome.data)
        self.outcome, self._request = outcome, request

    @property
    def card_toml(self) -> str:
        return self.data["card"]["toml"]

    def to_pandas(self):
        """One row per measured point of each data set (not a specimen's readings): ``dataset``,
        ``kind``, ``role``, ``stretch`` (the controlled stretch, or shear γ), ``stretch_2`` (a
        biaxial test's λ2), ``direction`` (biaxial: 1 or 2), ``measured`` and ``fitted`` stress
        (MPa, the data set's stress measure) and ``relative_residual`` = ``(fitted − measured) /
        max(abs(measured), 0.01 · max(abs(measured)))`` (the floor: 1 % of the set's largest stress),
        whose rms is fit.json's ``rms_relative``."""
        import numpy as np

        from vlab.identify.fitting import curves

        parts = []
        for d in (s for s in self.outcome.spec.datasets if s.kind not in ("specimen", "field")):
            y, n = np.asarray(d.y, float), len(d.a)
            fitted = np.real(np.asarray(curves(self.outcome, d)["at_data"], float))
            floor = 0.01 * np.max(np.abs(y))
            j = np.arange(len(y)) % n
            parts.append({"dataset": [d.name] * len(y), "kind": [d.kind] * len(y), "role": [d.role] * len(y),
                          "stretch": np.asarray(d.a, float)[j],
                          "stretch_2": np.asarray(d.b, float)[j] if d.b is not None else [None] * len(y),
                          "direction": 1 + np.arange(len(y)) // n, "measured": y, "fitted": fitted,
                          "relative_residual": (fitted - y) / np.maximum(np.abs(y), floor if floor > 0 else 1.0)})
        return frame({k: [v for p in parts for v in p[k]] for k in parts[0]} if parts else {})

    def write_report(self, folder: str | Path, force: bool = False) -> Path:
        """The folder ``vlab fit`` writes (fit.json, card.toml, figures, index.html); its index.html."""
        from vlab.identify.command import _destination
        from vlab.identify.report import write_fit_report

        dest = _destination(Path(folder), force, self.outcome.spec, self._request.path)
        self.data = write_fit_report(self.outcome, dest, self._request.text)
        return dest.path / "index.html"


class Ranking(Record):
    """Several models fitted to the same data and ranked: ranking.json's fields (``name``,
    ``ranking``: one row per model, best first), ``fits`` (each model's :class:`Fit`), ``best``,
    ``to_pandas()`` (the ranking table) and ``write_report(folder)``."""

    _what = "ranking.json"

    def __init__(self, request, ranked):
        from vlab.identify.ranking import ranking_rows
        from vlab.identify.report import strict

        self._request, self._ranked = request, ranked
        self.fits = {name: Fit(outcome, request) for name, outcome in ranked}
        super().__init__({"name": request.spec.name, "ranking": strict(ranking_rows(ranked))})

    @property
    def best(self) -> Fit:
        return self.fits[self.data["ranking"][0]["model"]]

    def to_pandas(self):
        """One row per model, best first: rank, model, the errors, BIC, AIC, the flags (the
        per-data-set errors and parameters, which are dicts, are left to ``ranking``)."""
        rows = [{k: v for k, v in r.items() if not isinstance(v, dict)} for r in self.data["ranking"]]
        return frame(rows=[list(r.values()) for r in rows], headers=list(rows[0]))

    def write_report(self, folder: str | Path, force: bool = False) -> Path:
        """The folder ``vlab fit --models`` writes (ranking.json, a fit folder per model, index.html)."""
        from vlab.identify.command import _destination
        from vlab.identify.ranking import write_ranking

        dest = _destination(Path(folder), force, self._request.spec, self._request.path)
        write_ranking(self._request.spec, self._ranked, dest, self._request.text)
        return dest.path / "index.html"
