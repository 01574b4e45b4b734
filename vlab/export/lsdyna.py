"""LS-DYNA keyword material cards (LS-DYNA Keyword User's Manual Vol. II: *MAT_077_H
*MAT_HYPERELASTIC_RUBBER, *MAT_077_O *MAT_OGDEN_RUBBER; Vol. I "General card format" for the
long format; Theory Manual, material models 77).

- *MAT_HYPERELASTIC_RUBBER with N = 0 (coefficients given, not fitted by LS-DYNA):
  W = Σ Cpq (J̄₁ − 3)^p (J̄₂ − 3)^q + W_H(J), J̄₁ = I₁ I₃^(−1/3), J̄₂ = I₂ I₃^(−2/3),
  W_H = K/2 (J − 1)² (vlab's "quadratic"); card 2: C10, C01, C11, C20, C02, C30, THERML.
  vlab's mooney-rivlin is (C10, C01) and its yeoh (C10, C20, C30), the others 0.
- *MAT_OGDEN_RUBBER with N = 0: W = Σᵢ Σⱼ μⱼ/αⱼ (λ̄ᵢ^αⱼ − 1) + K (J − 1 − ln J), up to 8 terms;
  card 2: MU1 … MU8, card 3: ALPHA1 … ALPHA8. μⱼ(LS-DYNA) = 2 μⱼ(vlab)/αⱼ (as ANSYS'). Its
  volumetric energy K (J − 1 − ln J) is none of vlab's, so only an incompressible fit's stand-in
  K is written to it (the fit determines the isochoric energy alone; same K, said in the header).

The bulk term is given as Poisson's ratio PR (card 1: MID, RO, PR, N, NV, G, SIGF, REF), from
which LS-DYNA takes K = 2 G₀ (1 + ν)/(3 (1 − 2ν)) with the initial shear modulus G₀
(2 (C10 + C01) for *MAT_077_H, ½ Σ μⱼ αⱼ for *MAT_077_O, both = vlab's μ0). vlab writes the ν of
that relation exactly: ν = (3K − 2μ0)/(2 (3K + μ0)), in fixed point with 17 decimals (a stand-in
ν = 0.4995 loses no digits of K = 2μ0(1 + ν)/(3(1 − 2ν)) beyond what a double ν carries: about
1e-16 · K/μ0 relative). Every card is in long format (the keyword suffix "+": 20-character
fields, LS-DYNA 971 R7.1 onwards), so the constants carry 13 significant digits.

Refused: Gent (LS-DYNA has no Gent rubber), vlab's coupled neo-hookean, and Arruda–Boyce
(*MAT_ARRUDA_BOYCE_RUBBER's bulk term is not one vlab has been able to match to its U(J)).
The reader takes the first of those two keywords (optionally _TITLE), in long, fixed (10-character)
or comma-separated free format, refuses N > 0 (a curve LS-DYNA fits itself) and names the line.
"""

from __future__ import annotations

from vlab.export.card import ExportCard, Source
from vlab.export.header import commented, header
from vlab.export.registry import CardFormatError, Exporter, Mapping

__all__ = ["LSDYNA", "poisson_of", "bulk_of"]

_MANUAL = "LS-DYNA Keyword User's Manual Vol. II, *MAT_077_H / *MAT_077_O (N = 0); Vol. I long format"
MAPPINGS = {
    "mooney-rivlin": Mapping("*MAT_HYPERELASTIC_RUBBER", "quadratic", _MANUAL),
    "yeoh": Mapping("*MAT_HYPERELASTIC_RUBBER", "quadratic", _MANUAL),
    "ogden": Mapping("*MAT_OGDEN_RUBBER", "K (J − 1 − ln J)", _MANUAL, max_terms=8),
}
NOTES = {"gent": "LS-DYNA has no Gent rubber",
         "arruda-boyce": "the bulk term of *MAT_ARRUDA_BOYCE_RUBBER is not matched to a vlab U(J)",
         "neo-hookean": "vlab's neo-hookean is the coupled μ/2 (I₁ − 3) − μ ln J + λ/2 ln²J; use "
                        "model = \"mooney-rivlin\" with C01 = 0 for the split form"}
CONVENTION = {
    "mooney-rivlin": "W = C10 (J1 − 3) + C01 (J2 − 3) + K/2 (J − 1)², K = 2 G0 (1 + PR)/(3 (1 − 2 PR)), G0 = 2 (C10 + C01)",
    "yeoh": "W = C10 (J1 − 3) + C20 (J1 − 3)² + C30 (J1 − 3)³ + K/2 (J − 1)², K = 2 G0 (1 + PR)/(3 (1 − 2 PR)), G0 = 2 C10",
    "ogden": "W = Σi Σj μj/αj (λ̄i^αj − 1) + K (J − 1 − ln J): μj(LS-DYNA) = 2 μj(vlab)/αj; K from PR with G0 = ½ Σ μj αj",
}
_U = {"quadratic": "K/2 (J − 1)² with K from PR", "K (J − 1 − ln J)": "K (J − 1 − ln J) with K from PR"}


def poisson_of(K: float, mu0: float) -> float:
    """ν of K and μ0 (the isotropic relation LS-DYNA inverts)."""
    return (3.0 * K - 2.0 * mu0) / (2.0 * (3.0 * K + mu0))


def bulk_of(nu: float, mu0: float) -> float:
    return 2.0 * mu0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))


def _f(v: float) -> str:
    return f"{float(v):20.12e}"


def _card1(card: ExportCard, units) -> str:
    rho = _f(0.0 if card.density is None else card.density * units.density)
    nu = f"{poisson_of(card.K, card.mu0):20.17f}"
    return f"{1:>20d}{rho}{nu}{0:>20d}\n"


def write(card: ExportCard, units) -> str:
    m, s, p = MAPPINGS[card.model], units.stress, card.params
    lines = header(card, "lsdyna", m.keyword, CONVENTION[card.model], units, _MANUAL, _U[m.volumetric])
    if card.density is None:
        lines.append("density not given in the vlab card: RO = 0, set it before an explicit run")
    out = commented(lines, "$") + f"{m.keyword}+\n"
    out += "$" + "".join(f"{k:>20}" for k in ("mid", "ro", "pr", "n"))[1:] + "\n" + _card1(card, units)
    if card.model == "ogden":
        mu = [2.0 * x / a * s for x, a in zip(p["mu"], p["alpha"])]
        out += "".join(_f(v) for v in mu) + "\n" + "".join(_f(a) for a in p["alpha"]) + "\n"
        return out
    c = {"C10": p["C10"], "C01": p.get("C01", 0.0), "C11": 0.0, "C20": p.get("C20", 0.0), "C02": 0.0,
         "C30": p.get("C30", 0.0)}
    out += "$" + "".join(f"{k.lower():>20}" for k in c)[1:] + "\n" + "".join(_f(v * s) for v in c.values()) + "\n"
    return out


# --- reading ---------------------------------------------------------------------------------
_KEYS = {"*MAT_HYPERELASTIC_RUBBER": "H", "*MAT_077_H": "H", "*MAT_OGDEN_RUBBER": "O", "*MAT_077_O": "O"}


def _fields(line: str, width: int) -> list[str]:
    if "," in line:
        return [x.strip() for x in line.split(",")]
    return [line[i:i + width].strip() for i in range(0, len(line.rstrip()), width)]


def _num(text: str, n: int, where: str, default: float = 0.0) -> float:
    if not text:
        return default
    try:
        return float(text)
    except ValueError:
        raise CardFormatError(f"{where}, line {n}: {text!r} is not a number") from None


def _find(text: str, where: str):
    """(keyword line, kind, width, [(line, fields)] of its data cards)."""
    lines = text.splitlines()
    long_all = any(l.strip().upper().startswith("*KEYWORD") and "LONG=Y" in l.upper() for l in lines)
    for i, raw in enumerate(lines):
        key = raw.strip().upper()
        if not key.startswith("*"):
            continue
        plus = key.endswith("+")
        base = key.rstrip("+").strip()
        title = base.endswith("_TITLE")
        base = base[:-6] if title else base
        if base not in _KEYS:
            if base.startswith("*MAT"):
                raise CardFormatError(f"{where}, line {i + 1}: {base} is not read by vlab (allowed: {', '.join(_KEYS)})")
            continue
        width = 20 if (plus or long_all) else 10
        cards = []
        for j in range(i + 1, len(lines)):
            l = lines[j]
            if l.strip().startswith("*"):
                break
            if l.strip().startswith("$") or not l.strip():
                continue
            cards.append((j + 1, _fields(l, width)))
        return i + 1, _KEYS[base], cards[1:] if title else cards
    raise CardFormatError(f"{where}: no *MAT_HYPERELASTIC_RUBBER or *MAT_OGDEN_RUBBER keyword")


_OGDEN_NOTE = ("LS-DYNA's *MAT_OGDEN_RUBBER has U = K (J − 1 − ln J), which vlab does not have: the card keeps K "
               "with vlab's quadratic U, so it equals the LS-DYNA card in every incompressible state and in "
               "its initial bulk modulus, not in a finite volume change")


def read(text: str, where: str, units) -> ExportCard:
    from vlab.export.card import card_from_table, material_table

    n, kind, cards = _find(text, where)
    need = 3 if kind == "O" else 2
    if len(cards) < need:
        raise CardFormatError(f"{where}, line {n}: the keyword needs {need} data cards (with N = 0), got {len(cards)}")
    rho, nu = _first_card(cards[0], where)
    if kind == "O":
        model, params, mu0 = _ogden_params(cards[1], cards[2], where, units.stress)
    else:
        model, params, mu0 = _rubber_params(cards[1], where, units.stress)
    note = _OGDEN_NOTE if kind == "O" else None
    base = ExportCard(model, params, bulk_of(nu, mu0), "quadratic", rho / units.density if rho > 0 else None)
    return card_from_table(material_table(base), where, stand_in=kind == "O",
                           source=Source("import", where, note=note))


def _first_card(card, where: str) -> tuple[float, float]:
    """(RO, PR) of card 1 (MID, RO, PR, N, …); N must be 0 and PR in (−1, 0.5)."""
    l1, c1 = card
    c1 = c1 + [""] * 8
    rho, nu, N = _num(c1[1], l1, where), _num(c1[2], l1, where, 0.0), _num(c1[3], l1, where)
    if N != 0:
        raise CardFormatError(f"{where}, line {l1}: N = {N:g}: LS-DYNA fits the constants to a curve itself; "
                              "vlab reads given constants only (N = 0)")
    if not -1.0 < nu < 0.5:
        raise CardFormatError(f"{where}, line {l1}: PR = {nu:g} must be in (−1, 0.5) for a compressible card")
    return rho, nu


def _ogden_params(mu_card, alpha_card, where: str, s: float):
    """("ogden", params, μ0) of cards 2 and 3 (MU1 …, ALPHA1 …): μ(vlab) = μ(LS-DYNA) α/2."""
    (lm, mu_f), (la, al_f) = mu_card, alpha_card
    mu_ls = [_num(x, lm, where) for x in mu_f if x]
    alpha = [_num(x, la, where) for x in al_f if x]
    terms = [(m, a) for m, a in zip(mu_ls + [0.0] * 8, alpha + [0.0] * 8) if m != 0.0 or a != 0.0]
    if not terms or len(mu_ls) != len(alpha) or any(a == 0.0 for _, a in terms):
        raise CardFormatError(f"{where}, line {lm}: MU and ALPHA need the same number of terms, each α ≠ 0 "
                              f"(got {len(mu_ls)} μ and {len(alpha)} α)")
    params = {"mu": tuple(m * a / 2.0 / s for m, a in terms), "alpha": tuple(a for _, a in terms)}
    return "ogden", params, sum(params["mu"])


def _rubber_params(card, where: str, s: float):
    """(model, params, μ0 = 2 (C10 + C01)) of card 2 (C10, C01, C11, C20, C02, C30): Yeoh when C20
    or C30 is given, else Mooney–Rivlin; C11, C02 or C01 with C20/C30 are refused."""
    lc, cf = card
    C10, C01, C11, C20, C02, C30 = [_num(x, lc, where) / s for x in (cf + [""] * 6)[:6]]
    if C11 or C02 or (C01 and (C20 or C30)):
        raise CardFormatError(f"{where}, line {lc}: C11, C02 or C01 with C20/C30: not a vlab model "
                              "(Mooney–Rivlin: C10, C01; Yeoh: C10, C20, C30)")
    model = "yeoh" if (C20 or C30) else "mooney-rivlin"
    params = {"C10": C10, "C20": C20, "C30": C30} if model == "yeoh" else {"C10": C10, "C01": C01}
    return model, params, 2.0 * (C10 + C01)


LSDYNA = Exporter("lsdyna", "lsdyna.k", "$", MAPPINGS, write, read, notes=NOTES, doc=__doc__)
