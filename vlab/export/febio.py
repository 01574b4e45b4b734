"""FEBio ``<material>`` (FEBio User's Manual 3.4, §4.1.2 uncoupled materials — §4.1.2.9 Ogden:
``<c1>``, ``<m1>``, ``<k>`` — Mooney-Rivlin, Gent, Yeoh; §4.1.3 unconstrained materials:
neo-Hookean with E, v; checked against FEBio's
source, FEBioMech/FEUncoupledMaterial.h, FEMooneyRivlin, FEOgdenMaterial, FEGentMaterial,
FEYeoh, FENeoHookean, FEArrudaBoyce).

An uncoupled FEBio material is W = W̃(C̃) + U(J) with U(J) = k/2 (ln J)² (FEUncoupledMaterial:
p = U' = k ln J / J): vlab's "log" volumetric energy with k = K.

- "Mooney-Rivlin": W̃ = c1 (Ĩ₁ − 3) + c2 (Ĩ₂ − 3)                  c1 = C10, c2 = C01
- "Yeoh":          W̃ = Σᵢ cᵢ (Ĩ₁ − 3)^i, i = 1 … 6                  c1, c2, c3 = C10, C20, C30
- "Ogden":         W̃ = Σᵢ cᵢ/mᵢ² (λ̃₁^mᵢ + λ̃₂^mᵢ + λ̃₃^mᵢ − 3), N ≤ 6   cᵢ = 2 μᵢ(vlab), mᵢ = αᵢ
- "Gent":          W̃ = −(G Jm/2) ln(1 − (Ĩ₁ − 3)/Jm)                G = μ, Jm = Jm
- "neo-Hookean" (coupled, E and v): W = μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)², vlab's neo-hookean
  exactly, with E = μ(3λ + 2μ)/(λ + μ), v = λ/(2(λ + μ)).

Refused: a card with another volumetric form (set volumetric = "log"; an incompressible fit's
stand-in K is written as k), and Arruda–Boyce: FEBio's "Arruda-Boyce" (FEArrudaBoyce.cpp) sums
μ Σ aᵢ/N^(i−1) (Ĩ₁^i − 3^i) with aᵢ = i Cᵢ (0.5, 0.1, 11/350, 19/1750, 519/134750), not the
eight-chain series Cᵢ (1/2, 1/20, 11/1050, …) of vlab, Abaqus and ANSYS, and no N makes the two
equal. The file is a ``<Material>`` section (one material, id 1) to paste into a .feb file.

Viscoelastic part: ``type="uncoupled viscoelastic"`` (User's Manual §4.1.2 "Uncoupled
Viscoelastic"; FEUncoupledViscoElasticMaterial::DevStress) wraps the uncoupled material as
``<elastic>``: S = g0 Sₑ + Σᵢ gᵢ Hᵢ, Hᵢ = ∫ e^(−(t−s)/tᵢ) dSₑ/ds ds, Sₑ = J F⁻¹ σ̃ F⁻ᵀ the pulled-
back deviatoric stress of the base, pushed forward by the current F — vlab's Maxwell stresses
(vlab.materials.viscoelastic) with g0 = 1 (Sₑ the long-term response), gᵢ = βᵢ, tᵢ = τᵢ (s), at
most 6 terms, for a Neo-Hookean base (vlab.export.parts); the bulk k of the base is not relaxed.
vlab's coupled neo-hookean is refused (FEBio's coupled "viscoelastic" relaxes the whole stress, the
volumetric part too); an incompressible neo-hookean fit is written as Mooney-Rivlin c1 = μ/2,
c2 = 0. Mullins: FEBio's damage materials (FEDamageMaterial with a damage CDF) hold the damage of
the largest past criterion on unloading, they are not Ogden–Roxburgh's pseudo-elastic
η(ψ0, W_max): refused.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

from vlab.export.card import ExportCard, Source, with_parts
from vlab.export.header import header, num
from vlab.export.parts import imported, needs
from vlab.export.registry import CardFormatError, Exporter, Mapping

__all__ = ["FEBIO"]

_MANUAL = "FEBio User's Manual 3.4 §4.1.2 uncoupled materials (U = k/2 ln²J), §4.1.3 neo-Hookean; FEBioMech sources"
MAPPINGS = {
    "mooney-rivlin": Mapping("Mooney-Rivlin", "log", _MANUAL),
    "yeoh": Mapping("Yeoh", "log", _MANUAL),
    "ogden": Mapping("Ogden", "log", _MANUAL, max_terms=6),
    "gent": Mapping("Gent", "log", _MANUAL),
    "neo-hookean": Mapping("neo-Hookean", None, _MANUAL),
}
NOTES = {"arruda-boyce": "FEBio's Arruda-Boyce sums μ Σ i·Ci/N^(i−1) (Ĩ1^i − 3^i), not the eight-chain series"}
CONVENTION = {
    "mooney-rivlin": "W = c1 (Ĩ1 − 3) + c2 (Ĩ2 − 3) + k/2 (ln J)²: c1 = C10, c2 = C01, k = K",
    "yeoh": "W = Σ ci (Ĩ1 − 3)^i + k/2 (ln J)²: c1, c2, c3 = C10, C20, C30, k = K",
    "ogden": "W = Σ ci/mi² (λ̃1^mi + λ̃2^mi + λ̃3^mi − 3) + k/2 (ln J)²: ci = 2 μi(vlab), mi = αi, k = K",
    "gent": "W = −(G Jm/2) ln(1 − (Ĩ1 − 3)/Jm) + k/2 (ln J)²: G = μ, k = K",
    "neo-hookean": "W = μ/2 (I1 − 3) − μ ln J + λ/2 (ln J)², μ = E/(2(1 + v)), λ = E v/((1 + v)(1 − 2v))",
}


def _params(card: ExportCard, s: float) -> list[tuple[str, float]]:
    p = card.params
    if card.model == "neo-hookean":
        mu, lm = p["mu"], p["lambda"]
        return [("E", mu * (3 * lm + 2 * mu) / (lm + mu) * s), ("v", lm / (2 * (lm + mu)))]
    k = [("k", card.K * s)]
    if card.model == "mooney-rivlin":
        return [("c1", p["C10"] * s), ("c2", p["C01"] * s)] + k
    if card.model == "yeoh":
        return [("c1", p["C10"] * s), ("c2", p["C20"] * s), ("c3", p["C30"] * s)] + k
    if card.model == "gent":
        return [("G", p["mu"] * s), ("Jm", p["Jm"])] + k
    n = card.terms
    return ([(f"c{i + 1}", 2.0 * p["mu"][i] * s) for i in range(n)]
            + [(f"m{i + 1}", p["alpha"][i]) for i in range(n)] + k)


_VISCO = "uncoupled viscoelastic"
_PART = ('<material type="uncoupled viscoelastic"> (§4.1.2, FEUncoupledViscoElasticMaterial): S = g0 Se + Σ gi Hi, '
         "g0 = 1, gi = βi, ti = τi (s), the base as <elastic>")


def write(card: ExportCard, units) -> str:
    m = MAPPINGS[card.model]
    u = "k/2 (ln J)²" if m.volumetric else None
    ve = card.effects.get("viscoelastic")
    lines = header(card, "febio", f'<material type="{_VISCO if ve else m.keyword}">', CONVENTION[card.model], units,
                   _MANUAL, u, (_PART,) if ve else ())
    body = "".join(f"    {line.replace('--', '- -')}\n" for line in lines)
    name = (card.name or "vlab").replace('"', "'").replace("&", "and").replace("<", "(").replace(">", ")")
    out = f'<?xml version="1.0" encoding="UTF-8"?>\n<!--\n{body}-->\n<Material>\n'
    out += f'  <material id="1" name="{name}" type="{_VISCO if ve else m.keyword}">\n'
    if card.density is not None:
        out += f"    <density>{num(card.density * units.density)}</density>\n"
    params = "".join(f"    <{k}>{num(v)}</{k}>\n" for k, v in _params(card, units.stress))
    if ve:
        out += "    <g0>1</g0>\n" + "".join(f"    <g{i + 1}>{num(g)}</g{i + 1}>\n    <t{i + 1}>{num(t)}</t{i + 1}>\n"
                                          for i, (g, t) in enumerate(zip(ve["beta"], ve["tau"])))
        out += f'    <elastic type="{m.keyword}">\n' + params.replace("    <", "      <") + "    </elastic>\n"
    else:
        out += params
    return out + "  </material>\n</Material>\n"


# --- reading ---------------------------------------------------------------------------------
_TYPES = {m.keyword: k for k, m in MAPPINGS.items()}


def _value(el, key: str, where: str) -> float | None:
    child = el.find(key)
    if child is None:
        return None
    try:
        return float((child.text or "").strip())
    except ValueError:
        raise CardFormatError(f"{where}: <{key}> of the material holds {child.text!r}, not a number") from None


def _need(el, keys, where: str, kind: str) -> list[float]:
    out = []
    for k in keys:
        v = _value(el, k, where)
        if v is None:
            raise CardFormatError(f"{where}: FEBio material type {kind!r} needs <{k}>")
        out.append(v)
    return out


def read(text: str, where: str, units) -> ExportCard:
    from vlab.export.card import card_from_table, material_table

    el, where = _material_element(text, where)
    parts, outer = {}, el
    if el.get("type") == _VISCO:
        parts = {"viscoelastic": _prony(el, where)}
        el = el.find("elastic")
        if el is None:
            raise CardFormatError(f"{where}: an {_VISCO!r} material needs its <elastic> base material")
    kind = el.get("type", "")
    if kind not in _TYPES:
        raise CardFormatError(f"{where}: FEBio material type {kind!r} is not read by vlab (allowed: {', '.join(_TYPES)})")
    model, s = _TYPES[kind], units.stress
    if model == "neo-hookean":
        E, v = _need(el, ("E", "v"), where, kind)
        mu, lm = E / (2 * (1 + v)) / s, E * v / ((1 + v) * (1 - 2 * v)) / s
        base = ExportCard(model, {"mu": mu, "lambda": lm}, None, None)
    else:
        (k,) = _need(el, ("k",), where, kind)
        base = ExportCard(model, _uncoupled_params(el, model, where, kind, s), k / s, "log")
    rho = _value(outer, "density", where)
    base = ExportCard(base.model, base.params, base.K, base.volumetric, None if rho is None else rho / units.density)
    card = card_from_table(material_table(base), where, name=outer.get("name") or "vlab", source=Source("import", where))
    try:
        return imported(with_parts(card, parts, where), where, "febio", any_J=("viscoelastic",))
    except ValueError as exc:
        raise CardFormatError(str(exc)) from None


def _prony(el, where: str) -> dict:
    """{"tau", "beta"} of an uncoupled viscoelastic material: the terms i = 1 … 6 with a <gi> or <ti>."""
    g0 = _value(el, "g0", where)
    if g0 is not None and g0 != 1.0:
        raise CardFormatError(f"{where}: <g0> = {g0:g}: vlab reads g0 = 1 (the base is the long-term response)")
    terms = [i for i in range(1, 7) if el.find(f"g{i}") is not None or el.find(f"t{i}") is not None]
    if not terms:
        raise CardFormatError(f"{where}: an {_VISCO!r} material without <g1> … <g6>")
    return {"tau": [_value(el, f"t{i}", where) or 1.0 for i in terms],  # FEBio's default tᵢ is 1
            "beta": [_value(el, f"g{i}", where) or 0.0 for i in terms]}


def _material_element(text: str, where: str):
    """(the first <material> element, ``where`` with its line) of an FEBio file."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise CardFormatError(f"{where}, line {exc.position[0]}: not well-formed XML ({exc})") from None
    el = root if root.tag == "material" else root.find(".//material")
    if el is None:
        raise CardFormatError(f"{where}: no <material> element")
    at = text.find("<material")
    return el, f"{where}, line {text.count(chr(10), 0, max(at, 0)) + 1} (<material>)"


def _uncoupled_params(el, model: str, where: str, kind: str, s: float) -> dict:
    """vlab's constants of an uncoupled FEBio material (the inverse of _params; stress / s)."""
    if model == "mooney-rivlin":
        c1, c2 = _need(el, ("c1", "c2"), where, kind)
        return {"C10": c1 / s, "C01": c2 / s}
    if model == "yeoh":
        c = [(_value(el, f"c{i}", where) or 0.0) / s for i in range(1, 7)]
        if any(c[3:]):
            raise CardFormatError(f"{where}: FEBio Yeoh with c4 … c6 ≠ 0: vlab's Yeoh has three terms")
        return {"C10": c[0], "C20": c[1], "C30": c[2]}
    if model == "gent":
        G, Jm = _need(el, ("G", "Jm"), where, kind)
        return {"mu": G / s, "Jm": Jm}
    return _ogden_params(el, where, s)


def _ogden_params(el, where: str, s: float) -> dict:
    """μᵢ = cᵢ/2, αᵢ = mᵢ of the terms with cᵢ ≠ 0 (each needs mᵢ ≠ 0)."""
    c = [_value(el, f"c{i}", where) for i in range(1, 7)]
    mm = [_value(el, f"m{i}", where) for i in range(1, 7)]
    terms = [(ci, mi) for ci, mi in zip(c, mm) if ci not in (None, 0.0)]
    if not terms or any(mi in (None, 0.0) for _, mi in terms):
        raise CardFormatError(f"{where}: FEBio Ogden needs c_i with a nonzero m_i for each term")
    return {"mu": tuple(ci / 2.0 / s for ci, _ in terms), "alpha": tuple(mi for _, mi in terms)}


FEBIO = Exporter("febio", "febio.feb", "", MAPPINGS, write, read, notes=NOTES, doc=__doc__,
                 parts=("hyperelastic", "viscoelastic"),
                 check_parts=lambda c: needs(c, "febio", max_terms=6, any_J=("viscoelastic",)))
