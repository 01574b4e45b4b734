"""`vlab export`, `vlab import-card` and the cards of `vlab fit --export`.

Exit codes as everywhere (vlab.cli_io): 0 written, 2 invalid input or a refused (model, target)
pair — with nothing written. A file vlab did not write (its first lines lack the header's
"vlab material card" / "vlab import-card") is never replaced unless ``--force``; files are
written whole (a temporary file renamed into place).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from vlab.fields import SceneError

__all__ = ["export_command", "export_texts", "import_command", "check_targets", "fit_card_writer", "parse_targets"]

_MARKS = ("vlab material card", "vlab import-card")


class ExportError(ValueError):
    """A refused export (the message names the targets that have the card)."""


def parse_targets(text: str) -> list[str]:
    from vlab.export import EXPORTERS

    names = [t.strip().lower() for t in text.split(",") if t.strip()]
    bad = [t for t in names if t not in EXPORTERS]
    if not names or bad:
        raise SceneError(f"--to/--export: unknown solver {', '.join(bad) or '(none)'}; allowed: {', '.join(EXPORTERS)}")
    return list(dict.fromkeys(names))


def _units(name: str):
    from vlab.export.header import UNITS

    key = {"mm": "mm", "si": "SI"}.get(name.lower())
    if key is None:
        raise SceneError(f"--units must be mm (N, mm, MPa, s, t/mm³) or SI (N, m, Pa, s, kg/m³), got {name!r}")
    return UNITS[key]


def card_text(card, target: str, units) -> str:
    """The file text of ``card`` for ``target``; ExportError if the target has no exact card."""
    from vlab.export import EXPORTERS
    from vlab.export.registry import form_for, refusal

    why = refusal(target, card)
    if why is not None:
        raise ExportError(why)
    return EXPORTERS[target].write(form_for(target, card), units)


def _ours(path: Path) -> bool:
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            head = fh.read(2000)
    except OSError:
        return False
    return any(m in head for m in _MARKS)


def write_file(path: Path, text: str, force: bool) -> None:
    """Write ``text`` whole; refuse to replace a file vlab did not write (unless forced)."""
    path = Path(path)
    if path.is_dir():
        raise SceneError(f"--out {path} is a folder; give a file name")
    if path.exists() and not force and not _ours(path):
        raise SceneError(f"--out {path} exists and was not written by vlab; use --force to replace it")
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def export_texts(card, solvers: list[str], units: str = "mm", elastic_only: bool = False) -> dict[str, str]:
    """The file text of ``card`` (vlab.export.card.ExportCard) for each solver, in ``units`` (mm or
    SI), without its viscoelastic/Mullins parts when ``elastic_only``; SceneError for bad units,
    ExportError naming the solvers that have the card when one has none."""
    from vlab.export import card as cards

    u = _units(units)
    if elastic_only:
        card = cards.elastic_only(card)
    return {t: card_text(card, t, u) for t in solvers}


def export_command(source: Path, to: str, out: Path | None, units: str, elastic_only: bool, force: bool,
                   say, show=None) -> int:
    """Write the card of ``source`` for the solvers in ``to`` (module docstring); a refusal is said
    with ``say`` (stderr in the CLI), the files written with ``show`` (stdout; default ``say``)."""
    from vlab.export import EXPORTERS
    from vlab.export import card as cards

    try:
        solvers = parse_targets(to)
        _units(units)  # a bad --units is named before the source is read
        if out is not None and len(solvers) > 1:
            raise SceneError("--out names one file; give one solver with --to, or no --out")
        texts = export_texts(cards.load_source(source), solvers, units, elastic_only)  # every refusal before any file
        paths = {t: Path(out) if out is not None else Path(EXPORTERS[t].default_file) for t in solvers}
        for t in solvers:
            write_file(paths[t], texts[t], force)
    except (SceneError, ExportError) as exc:
        say(("cannot export", "red"), f" {str(exc).removeprefix('cannot export').lstrip()}")  # refusals say it once
        return 2
    for t in solvers:
        (show or say)(f"{t}: {paths[t]}")
    return 0


def _detect(text: str, suffix: str) -> str | None:
    up = text.upper()
    if "*HYPERELASTIC" in up:
        return "abaqus"
    if "TB,HYPER" in up.replace(" ", ""):
        return "ansys"
    if "*MAT_" in up:
        return "lsdyna"
    if "<MATERIAL" in up:
        return "febio"
    if suffix == ".py" or "UMAT" in up:
        return "felupe"
    return None


def read_card(path: Path, solver: str | None, units: str | None):
    """(ExportCard, solver) of a solver card file."""
    from vlab.export import EXPORTERS
    from vlab.export.header import units_of_header
    from vlab.export.registry import CardFormatError

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"cannot read {path}: {exc}") from None
    name = solver.lower() if solver else _detect(text, path.suffix.lower())
    if name not in EXPORTERS:
        raise SceneError(f"{path}: cannot tell the solver format; give --from ({', '.join(EXPORTERS)})")
    u = _units(units) if units else _units(units_of_header(text))
    try:
        return EXPORTERS[name].read(text, str(path), u), name
    except CardFormatError as exc:
        raise SceneError(str(exc)) from None


def import_toml(card, path: Path, solver: str) -> str:
    from vlab.export.card import material_table
    from vlab.identify.card import card_toml

    lines = [f"# vlab import-card: the {card.describe()} of {path} ({solver})"]
    if card.source is not None and card.source.note:
        lines.append(f"# {card.source.note}")
    text = card_toml(material_table(card))
    for part, table in card.effects.items():  # the parts as the scene grammar's [effects.*] tables
        text += f"\n[effects.{part}]\n" + card_toml(
            {k: list(v) if isinstance(v, tuple) else v for k, v in table.items()}).split("\n", 1)[1]
    return "\n".join(lines) + "\n" + text


def import_command(path: Path, out: Path | None, solver: str | None, units: str | None, force: bool, say,
                   show=None) -> int:
    """Read a solver card into a vlab [material] card (card.toml or --out); a refusal with ``say``
    (stderr), the card and its file with ``show`` (stdout; default ``say``)."""
    try:
        card, name = read_card(path, solver, units)
        text = import_toml(card, Path(path), name)
        target = Path(out) if out is not None else Path("card.toml")
        write_file(target, text, force)
    except SceneError as exc:
        say(("cannot import card", "red"), f" {exc}")
        return 2
    (show or say)(text.rstrip())
    (show or say)(f"card: {target}")
    return 0


# --- vlab fit --export -------------------------------------------------------------------------
def _provisional(spec):
    """A card with the fit's model, terms, volumetric, bulk and parts (enough for ``refusal``):
    constants the fit determines are placeholders that are generic (a fitted C01 or α is taken
    as not 0 or 2), so a target is refused before the fit when the fitted card would be."""
    from vlab.export.card import ExportCard

    law, model = spec.model.law, spec.model
    params = {"neo-hookean": {"mu": 1.0, "lambda": 1.0}, "mooney-rivlin": {"C10": 1.0, "C01": 1.0},
              "yeoh": {"C10": 1.0, "C20": 1.0, "C30": 1.0},
              "ogden": {"mu": (1.0,) * law.terms, "alpha": (1.0,) * law.terms}}.get(law.model, {})
    fe = getattr(spec, "fe", None)  # FE in the loop: the card is the scene's compressible material
    vol = None if law.model == "neo-hookean" else ((fe or {}).get("volumetric") or model.volumetric)
    stand_in = fe is None and model.bulk == "incompressible"
    effects = {}
    prony, mullins = (getattr(spec, "effects", None) or {}).get("viscoelastic"), (
        getattr(spec, "effects", None) or {}).get("mullins")
    if prony is not None:
        effects["viscoelastic"] = {"tau": (1.0,) * prony.terms, "beta": (1.0,) * prony.terms}
    if mullins is not None:
        effects["mullins"] = {"r": 2.0, "m": 1.0, "beta": 0.0}
    return ExportCard(law.model, params, 1.0, vol, stand_in=stand_in,
                      parts=("hyperelastic",) + tuple(effects), effects=effects)


def check_targets(spec, text: str) -> list[str]:
    """The --export solvers, each able to write the fit's card (SceneError naming the refusal)."""
    from vlab.export.registry import refusal

    targets = parse_targets(text)
    card = _provisional(spec)
    for t in targets:
        why = refusal(t, card)
        if why is not None:
            raise SceneError(f"--export {t}: {why}")
    return targets


def fit_card_writer(outcome, targets: list[str], units: str = "mm"):
    """A report-folder writer (outcome.extras["writers"]) that writes cards/<file> of each target
    and lists them in the fit dict (``cards``) for the page and fit.json → files."""
    from vlab.export import EXPORTERS
    from vlab.export.card import card_of_fit

    def write(folder: Path) -> None:
        d = outcome.data
        card = card_of_fit(d, "fit.json")
        folder.mkdir()
        u = _units(units)
        d["cards"] = []
        for t in targets:
            name = EXPORTERS[t].default_file
            (folder / name).write_text(card_text(card, t, u), encoding="utf-8")
            d["cards"].append(f"cards/{name}")
    return write
