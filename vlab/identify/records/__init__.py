"""Lab records for `vlab fit`: raw machine exports and time/frequency records of viscoelastic tests.

raw.py         a force–displacement export with geometry → a cleaned stretch–stress curve
               (units by pint, zero = none|first|toe, trim, resample, smooth), a normal data set
prony.py       [model] viscoelastic = {terms} | {tau}; the homogeneous history of vlab's effect
relaxation.py  kind "relaxation": time, stretch, stress of a whole record (ramp and hold)
dma.py         kind "dma": storage and loss moduli over frequency
cyclic.py      kind "cyclic": loading–unloading cycles; softening.py: [model] mullins (Ogden–Roxburgh)
fit.py         the fit of records (with any homogeneous curves): ground law + Prony series
plots.py       the figures: records against the model, raw against cleaned data

Contract of a record kind (one module in ``KINDS``): ``KIND`` its name; ``parse(raw, i, base)``
→ Dataset (validated, SceneError naming file/row/column); ``predict(model, effects, X, d)`` (effects: {"viscoelastic": PronySpec | None, "mullins":
MullinsSpec | None}) →
(m, len(d.y)) from internal coordinates X (m, n_x), analytic in X (complex step);
``NEEDS_PRONY`` whether it is meaningless without [model] viscoelastic; ``scale(d)`` a modulus
estimate (MPa) for the starts; ``time_range(d)`` the (shortest, longest) time scale (s) the
record resolves (None: untimed); ``curve(model, effects, x, d)`` → (x values, prediction); ``XLABEL``.
"""

from __future__ import annotations

from pathlib import Path

from vlab.identify.records import cyclic, dma, relaxation

__all__ = ["KINDS", "dataset_hook", "split_model", "is_record"]

KINDS = {m.KIND: m for m in (relaxation, dma, cyclic)}
MODEL_KEYS = ("viscoelastic", "mullins")


def dataset_hook(raw, i: int, base: Path):
    """The Dataset of a [[data]] table this package reads (a record kind or a raw export), else None."""
    from vlab.identify.records.raw import is_raw, raw_dataset

    if isinstance(raw, dict) and raw.get("kind") in KINDS:
        return KINDS[raw["kind"]].parse(raw, i, Path(base))
    if is_raw(raw):
        return raw_dataset(raw, i, Path(base))
    return None


def split_model(raw) -> tuple[dict, dict]:
    """([model] without this package's keys, {"viscoelastic": PronySpec | None, "mullins": MullinsSpec | None})."""
    from vlab.fields import SceneError
    from vlab.identify.records.prony import parse_viscoelastic
    from vlab.identify.records.softening import parse_mullins

    if not isinstance(raw, dict):
        return raw, {}
    rest = {k: v for k, v in raw.items() if k not in MODEL_KEYS}
    effects = {"viscoelastic": parse_viscoelastic(raw.get("viscoelastic")), "mullins": parse_mullins(raw.get("mullins"))}
    return rest, effects


def is_record(d) -> bool:
    return d.kind in KINDS


def check_records(model, effects: dict, datasets, fe) -> None:
    """What a fit with records needs: an incompressible ground law; a DMA record and a Prony
    series together; a Prony series with a timed record to fit it from; no FE in the loop."""
    records = [d for d in datasets if d.kind in KINDS]
    prony, mullins = effects.get("viscoelastic"), effects.get("mullins")
    if not records and prony is None and mullins is None:
        return
    from vlab.fields import SceneError

    if model.bulk != "incompressible":
        raise SceneError("records (kind = \"relaxation\" or \"dma\") and model.viscoelastic are fitted with an "
                         "incompressible ground law (homogeneous incompressible states); drop model.K / model.fit_K")
    if fe is not None:
        raise SceneError("records (kind = \"relaxation\" or \"dma\") cannot be fitted with FE in the loop "
                         "(kind = \"specimen\") in one fit file")
    for i, d in enumerate(datasets):
        if d.kind in KINDS and KINDS[d.kind].NEEDS_PRONY and prony is None:
            raise SceneError(f"data[{i}] ({d.name!r}, kind = {d.kind!r}) is a storage/loss modulus sweep: an "
                             "elastic model has no loss modulus; add [model] viscoelastic = { terms = 3 }")
    if mullins is not None and not any(d.kind == "cyclic" and d.role == "fit" for d in datasets):
        raise SceneError("model.mullins needs a cyclic record to fit (a data set of kind = \"cyclic\" with role = "
                         "\"fit\"): the softening shows only on unloading and reloading")
    for i, d in enumerate(datasets):
        if d.kind == "cyclic" and prony is not None and d.extra["time"] is None:
            raise SceneError(f"data[{i}] ({d.name!r}, kind = \"cyclic\") has no time column: with model.viscoelastic "
                             "the history needs columns.time (s)")
    if prony is not None and not any(KINDS[d.kind].time_range(d) is not None for d in datasets
                                     if d.kind in KINDS and d.role == "fit"):
        raise SceneError("model.viscoelastic needs a timed record to fit (a data set of kind = \"relaxation\" or "
                         "\"dma\" with role = \"fit\"): an equilibrium curve carries no relaxation time")
