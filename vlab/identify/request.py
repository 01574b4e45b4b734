"""What ``vlab fit`` and ``vlab.fit`` share: the fit file and the choices beside it (models to rank,
solvers to export to, Dask for the whole-test solves) checked before any work starts, then the fit
itself. Nothing here prints or writes; bad input is a SceneError naming the field."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from vlab.fields import SceneError

__all__ = ["FitRequest", "fit_request", "run_ranking", "run_single"]


@dataclass(frozen=True)
class FitRequest:
    """The loaded fit file (``path``, ``spec``, its ``text``), the models to fit and rank (``names``; None:
    the file's [model] alone) and the solvers whose cards the fit also writes (``targets``)."""

    path: Path
    spec: object
    text: str
    names: list[str] | None
    targets: list[str]


def model_names(models: str | Sequence[str] | None) -> list[str] | None:
    """--models "a,b" (or a list) -> ["a", "b"], each a known model name (SceneError otherwise)."""
    from vlab.identify.fitfile import parse_model_name

    if models is None:
        return None
    items = models.split(",") if isinstance(models, str) else list(models)
    names = [str(m).strip() for m in items if str(m).strip()]
    if not names:
        raise SceneError("--models must list at least one model, e.g. mooney-rivlin,ogden-3")
    seen: dict[tuple, str] = {}
    for n in names:  # none repeated ("ogden" and "ogden-1" are one model): a repeat failed late ("File exists")
        key = parse_model_name(n, "--models")
        if key in seen:
            same = "" if seen[key] == n else f" (the same model as {seen[key]!r})"
            raise SceneError(f"--models lists {n!r} more than once{same}: each model is fitted and ranked once")
        seen[key] = n
    return names


def fit_request(path: Path, models: str | Sequence[str] | None = None, export: str | None = None,
                distributed: bool = False) -> FitRequest:
    """The checked request; ``distributed``: --workers/--scheduler were given (they run an
    FE-in-the-loop fit's solves, so a fit without a specimen data set refuses them)."""
    from vlab.identify.fitfile import parse_fit_text, read_fit_text
    from vlab.identify.specimens import specimen_ids

    text = read_fit_text(path)  # read once: the text the report keeps is the text fitted
    spec = parse_fit_text(path, text)
    names = model_names(models)
    if names and any(d.kind in ("relaxation", "dma") for d in spec.datasets):
        raise SceneError("--models ranks equilibrium fits; a fit file with relaxation or DMA records is fitted "
                         "with its own [model] (leave out --models)")
    if names and any(d.kind == "field" for d in spec.datasets):
        raise SceneError("--models ranks models on curves; a fit file of DIC fields (kind = \"field\") is fitted "
                         "through its scene's own material model (leave out --models)")
    if names and len(specimen_ids(spec.datasets)) > 1:
        raise SceneError("--models ranks models on one data set; a fit file whose data sets name several specimens "
                         "is fitted per specimen and pooled with its own [model] (leave out --models)")
    targets = _export_targets(spec, export, names)
    if distributed and spec.fe is None:
        raise SceneError("--workers/--scheduler run the whole-test solves of an FE-in-the-loop fit; this fit "
                         "file has no data set of kind = \"specimen\"")
    return FitRequest(Path(path), spec, text, names, targets)


def _export_targets(spec, export: str | None, names) -> list[str]:
    """The --export solvers, refused (SceneError) with --models or where a target lacks the card."""
    if export is None:
        return []
    if names:
        raise SceneError("--export writes the cards of one fitted model; it cannot be combined with --models")
    from vlab.export.command import check_targets

    return check_targets(spec, export)


def run_ranking(request: FitRequest) -> list:
    """[(model name, FitOutcome)], best first (vlab.identify.ranking)."""
    from vlab.identify.ranking import fit_models

    return fit_models(request.spec, request.names)


def run_single(request: FitRequest, execution=None):
    """The FitOutcome of the file's [model] (homogeneous, records or FE-in-the-loop; its solves on
    Dask with ``execution``), with the --export cards' writer attached; a SceneError found while
    fitting (e.g. the scene's test does not cover the data) propagates."""
    from vlab.identify.fitting import fit_any

    outcome = fit_any(request.spec, execution)
    if request.targets:
        from vlab.export.command import fit_card_writer

        outcome.extras.setdefault("writers", []).append(("cards", fit_card_writer(outcome, list(request.targets))))
    return outcome
