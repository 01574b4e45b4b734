"""The card an exporter writes: a validated vlab ``[material]`` and where it came from.

``load_source(path)`` reads a ``vlab fit`` output folder, its ``fit.json``, its ``card.toml``
or any scene TOML, validates its ``[material]`` with the scene grammar
(vlab.materials.card.parse_material: a bad card is a SceneError naming the key) and returns an
``ExportCard``: model, constants (vlab's names and convention, MPa), bulk modulus K (MPa),
volumetric form, density (t/mm³), whether K is an incompressible fit's stand-in, the card
parts ("hyperelastic", and "viscoelastic" / "mullins" with their constants in ``effects`` from a
scene's or a fit's [effects.viscoelastic] / [effects.mullins], validated by vlab.export.parts) and,
for a fit, the fitted data ranges and the Drucker-stable stretch range per mode (fit.json →
stability, vlab.identify.drucker).

An incompressible fit determines only the isochoric energy: its K = r μ0 stands in for
incompressibility (vlab.identify.card) and its volumetric form is not part of the fit, so a
target's own U(J) with the same K is written for it (with a comment) where a fitted or given K
needs the very same U(J) (vlab.export.registry.refusal).
"""

from __future__ import annotations

import json
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

from vlab.fields import SceneError

__all__ = ["ExportCard", "Source", "load_source", "card_from_table", "card_of_fit", "material_table", "elastic_only",
           "forms", "with_parts"]


@dataclass(frozen=True)
class Source:
    kind: str                        # "fit" | "card" | "scene" | "import"
    path: str
    name: str | None = None          # the fit's name
    ranges: tuple = ()               # (data set, kind, role, lo, hi) of a fit
    stability: dict | None = None    # fit.json → stability.kinds
    note: str | None = None          # the card's note (why K is what it is)


@dataclass(frozen=True)
class ExportCard:
    model: str
    params: dict                     # vlab card constants (MPa; Ogden/lists as tuples); neo-hookean: mu, lambda
    K: float | None                  # MPa; None for the coupled neo-hookean law
    volumetric: str | None           # vlab.materials.volumetric name; None for neo-hookean
    density: float | None = None     # t/mm³
    stand_in: bool = False           # K stands in for incompressibility (an incompressible fit)
    name: str = "vlab"
    parts: tuple[str, ...] = ("hyperelastic",)
    source: Source | None = field(default=None, compare=False)
    effects: dict = field(default_factory=dict)   # part -> constants (vlab.export.parts.parse_parts)
    form: str | None = None          # why the card is written in another of vlab's forms (split neo-Hooke)

    @property
    def terms(self) -> int:
        return len(self.params["mu"]) if self.model == "ogden" else 1

    @property
    def mu0(self) -> float:
        """Initial shear modulus μ0 (MPa) from vlab's law."""
        p = self.params
        if self.model == "neo-hookean":
            return float(p["mu"])
        return float(_law(self).mu0)

    def describe(self) -> str:
        label = f"ogden-{self.terms}" if self.model == "ogden" else self.model
        vol = "" if self.volumetric is None else f", volumetric {self.volumetric}"
        extra = [p for p in self.parts if p != "hyperelastic"]
        return f"{label} card{vol}" + (f" with its {' and '.join(extra)} part{'s' if len(extra) > 1 else ''}" if extra else "")


def _law(card: ExportCard):
    from vlab.materials.registry import MODELS, MaterialCard

    @dataclass(frozen=True)
    class _Bulk:
        K: float

    entry = MODELS[card.model]
    return entry.build(MaterialCard(card.model, _Bulk(card.K), dict(card.params), card.volumetric))


def material_table(card: ExportCard) -> dict:
    """The card as a vlab ``[material]`` table (full precision)."""
    t = {"model": card.model}
    for k, v in card.params.items():
        t[k] = [float(x) for x in v] if isinstance(v, (list, tuple)) else float(v)
    if card.K is not None:
        t["K"] = float(card.K)
        if card.volumetric != "quadratic":
            t["volumetric"] = card.volumetric
    if card.density is not None:
        t["density"] = float(card.density) * 1e12  # kg/m³, as the card grammar takes it
    return t


def card_from_table(table: dict, where: str, **kw) -> ExportCard:
    """Validate a [material] table with the scene grammar and make the ExportCard."""
    from vlab.materials.card import parse_material

    try:
        spec = parse_material(table)
    except SceneError as exc:
        raise SceneError(f"{where}: {exc}") from None
    if spec.volumetric is None:  # the moduli grammar (neo-hookean and the small-strain laws)
        params = {"mu": spec.moduli.mu, "lambda": spec.moduli.lmbda}
        return ExportCard(spec.model, params, None, None, spec.density, **kw)
    params = {k: tuple(v) if isinstance(v, (list, tuple)) else float(v) for k, v in spec.params.items()}
    return ExportCard(spec.model, params, float(spec.moduli.K), spec.volumetric, spec.density, **kw)


def _read_toml(path: Path) -> tuple[dict, str]:
    try:
        text = path.read_text(encoding="utf-8")
        return tomllib.loads(text), text
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"cannot read {path}: {exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML: {exc}") from None


def _from_fit_json(path: Path) -> ExportCard:
    try:
        d = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise SceneError(f"{path}: not a vlab fit.json ({exc})") from None
    return card_of_fit(d, str(path))


def card_of_fit(d: dict, path: str) -> ExportCard:
    """The ExportCard of a fit's dict (fit.json)."""
    try:
        table, model = d["card"]["material"], d["model"]
    except (KeyError, TypeError) as exc:
        raise SceneError(f"{path}: not a vlab fit.json (no {exc})") from None
    ranges = tuple((x["name"], x["kind"], x["role"], float(x["range"][0]), float(x["range"][1]))
                   for x in d.get("datasets", []) if x.get("range"))
    source = Source("fit", path, d.get("name"), ranges, (d.get("stability") or {}).get("kinds"),
                    d["card"].get("note"))
    card = card_from_table(table, path, stand_in=model.get("bulk") == "incompressible",
                           name=d.get("name") or "vlab", source=source)
    return with_parts(card, d["card"].get("effects"), path)


def with_parts(card: ExportCard, effects: dict | None, where: str) -> ExportCard:
    """The card with the viscoelastic / Mullins parts of its [effects] tables (validated)."""
    from vlab.export.parts import parse_parts

    parsed = parse_parts(effects, where)
    return replace(card, parts=("hyperelastic",) + tuple(parsed), effects=parsed)


def _from_toml(path: Path) -> ExportCard:
    data, text = _read_toml(path)
    if "material" not in data:
        raise SceneError(f"{path}: no [material] table (give a fit folder, fit.json, card.toml or a scene)")
    first = text.lstrip().splitlines()[0] if text.strip() else ""
    stand_in = first.startswith("# incompressible fit")
    kind = "card" if set(data) == {"material"} else "scene"
    note = first[1:].strip() if first.startswith("#") else None
    card = card_from_table(data["material"], str(path), stand_in=stand_in, name=path.stem,
                           source=Source(kind, str(path), note=note))
    return with_parts(card, data.get("effects"), str(path))


def load_source(path: Path) -> ExportCard:
    """The ExportCard of a fit folder, fit.json, card.toml or scene (module docstring)."""
    path = Path(path)
    if path.is_dir():
        for name, reader in (("fit.json", _from_fit_json), ("card.toml", _from_toml)):
            if (path / name).is_file():
                return reader(path / name)
        raise SceneError(f"{path}: a folder without fit.json or card.toml (give a vlab fit output folder)")
    if not path.is_file():
        raise SceneError(f"{path}: no such file or folder")
    return _from_fit_json(path) if path.suffix == ".json" else _from_toml(path)


def elastic_only(card: ExportCard) -> ExportCard:
    """The card without its viscoelastic/Mullins parts (``--elastic-only``)."""
    return replace(card, parts=("hyperelastic",), effects={})


def forms(card: ExportCard) -> list[ExportCard]:
    """The card and the other forms of vlab's that are the same model: an incompressible
    neo-hookean fit is also the split neo-Hooke (vlab.export.parts.split_neo_hookean)."""
    if card.stand_in and card.model == "neo-hookean":
        from vlab.export.parts import split_neo_hookean

        return [card, split_neo_hookean(card)]
    return [card]
