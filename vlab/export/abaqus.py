"""Abaqus ``*HYPERELASTIC`` (Abaqus Analysis User's Guide §22.5.1 "Hyperelastic behavior of
rubberlike materials"; Keywords Reference "*HYPERELASTIC").

Abaqus writes U = ψ_iso(Ī₁, Ī₂ or λ̄ᵢ) + U_vol(J_el) with Ī = invariants of C̄ = J^(−2/3) C:

- MOONEY-RIVLIN:          U = C10 (Ī₁ − 3) + C01 (Ī₂ − 3) + (J − 1)²/D1          data: C10, C01, D1
- REDUCED POLYNOMIAL N=3: U = Σᵢ Ci0 (Ī₁ − 3)^i + Σᵢ (J − 1)^(2i)/Di           data: C10, C20, C30, D1, D2, D3
- OGDEN N (≤ 6):          U = Σᵢ 2μᵢ/αᵢ² (λ̄₁^αᵢ + λ̄₂^αᵢ + λ̄₃^αᵢ − 3) + Σᵢ (J − 1)^(2i)/Di
                          data: μ1, α1, …, μN, αN, D1, …, DN (eight per line)
- ARRUDA-BOYCE:           U = μ Σᵢ Cᵢ/λm^(2i−2) (Ī₁^i − 3^i) + (1/D) ((J² − 1)/2 − ln J)
                          data: μ, λm, D
- NEO HOOKE (read only):  U = C10 (Ī₁ − 3) + (J − 1)²/D1                        data: C10, D1

so vlab's constants are Abaqus' own (C10, C01, Ci0, μᵢ, αᵢ, μ, λm), D1 = 2/K with D2 = D3 = … = 0
(Abaqus: a zero Di, i ≥ 2, drops its term) and the volumetric energy is vlab's "quadratic"
((J − 1)²/D1 = K/2 (J − 1)²) for the polynomial and Ogden forms, "simo-taylor" for
Arruda–Boyce ((1/D)((J² − 1)/2 − ln J) = K/4 (J² − 1 − 2 ln J)). Abaqus has no Gent model
and its neo-Hooke is the split one (vlab's mooney-rivlin with C01 = 0), not vlab's compressible
neo-hookean: both are refused. vlab writes MOONEY-RIVLIN for a card with C01 = 0 (exact) and
reads NEO HOOKE, YEOH and REDUCED POLYNOMIAL N ≤ 3 as mooney-rivlin / yeoh.

Viscoelastic and Mullins parts (vlab.export.parts says when they are vlab's model: a
Neo-Hookean ground for the Prony part, an incompressible fit's card for both):

- ``*VISCOELASTIC, TIME=PRONY`` (Abaqus Analysis User's Guide §22.7.1 "Time domain
  viscoelasticity", Theory Guide §4.8.2 "Finite-strain viscoelasticity"): the deviatoric
  Kirchhoff stress relaxes as τᴰ(t) = τ₀ᴰ(t) + ∫ ġ_R(s) (push-forward of τ₀ᴰ(t − s)) ds with
  g_R(t) = 1 − Σᵢ gᵢ (1 − e^(−t/τᵢ)) — Simo's reference-configuration hereditary integral, the
  form vlab integrates. Data lines gᵢ, kᵢ, τᵢ. With ``MODULI=LONG TERM`` on ``*HYPERELASTIC``
  (written explicitly; Abaqus' default) the hyperelastic constants are the long-term ones and the
  instantaneous ones are them / (1 − Σgᵢ), so the shear relaxation modulus is
  μ∞ g_R(t)/g_R(∞) = μ0 (1 + Σ βᵢ e^(−t/τᵢ)) with gᵢ = βᵢ/(1 + Σβ) (vlab.export.parts.normalised),
  kᵢ = 0 (vlab's bulk modulus does not relax), τᵢ in s in both unit systems.
- ``*MULLINS EFFECT`` (Analysis User's Guide §22.6.1 "Mullins effect", Theory Manual §4.7 "Mullins effect"):
  η = 1 − (1/r) erf((U_m − Ũ_dev)/(m + β U_m)), Ũ_dev the primary deviatoric energy and U_m its
  maximum; data line r, m, β (m an energy density: MPa or Pa), vlab's r, m, β.

The reader takes the first ``*HYPERELASTIC`` (with its ``*MATERIAL`` name and ``*DENSITY``) and
the ``*VISCOELASTIC`` / ``*MULLINS EFFECT`` blocks, refuses TEST DATA INPUT (the coefficients
would be Abaqus' own fit), MODULI=INSTANTANEOUS, a bulk Prony term kᵢ ≠ 0, FREQUENCY or creep
/ relaxation test data for *VISCOELASTIC, POISSON, temperature or field dependence and any other
option, and names the line of every error.
"""

from __future__ import annotations

import re

from vlab.export.card import ExportCard, Source, with_parts
from vlab.export.header import commented, header, num
from vlab.export.parts import imported, needs, normalised, relative
from vlab.export.registry import CardFormatError, Exporter, Mapping

__all__ = ["ABAQUS", "MAPPINGS", "write_deck", "read_deck"]

_MANUAL = "Abaqus Analysis User's Guide §22.5.1 (Hyperelastic behavior of rubberlike materials); *HYPERELASTIC"
MAPPINGS = {
    "mooney-rivlin": Mapping("MOONEY-RIVLIN", "quadratic", _MANUAL),
    "yeoh": Mapping("REDUCED POLYNOMIAL, N=3", "quadratic", _MANUAL),
    "ogden": Mapping("OGDEN", "quadratic", _MANUAL, max_terms=6),
    "arruda-boyce": Mapping("ARRUDA-BOYCE", "simo-taylor", _MANUAL),
}
NOTES = {"gent": "Abaqus has no Gent model",
         "neo-hookean": "Abaqus' NEO HOOKE is the split C10 (Ī₁ − 3) + (J − 1)²/D1; vlab's neo-hookean "
                        "is the coupled μ/2 (I₁ − 3) − μ ln J + λ/2 ln²J — use model = \"mooney-rivlin\" "
                        "with C01 = 0 for the split form"}
CONVENTION = {
    "mooney-rivlin": "U = C10 (Ī1 − 3) + C01 (Ī2 − 3) + (J − 1)²/D1, D1 = 2/K",
    "yeoh": "U = Σ Ci0 (Ī1 − 3)^i + Σ (J − 1)^(2i)/Di, D1 = 2/K, D2 = D3 = 0",
    "ogden": "U = Σ 2μi/αi² (λ̄1^αi + λ̄2^αi + λ̄3^αi − 3) + Σ (J − 1)^(2i)/Di: μi, αi are vlab's; D1 = 2/K, Di>1 = 0",
    "arruda-boyce": "U = μ Σ Ci/λm^(2i−2) (Ī1^i − 3^i) + (1/D)((J² − 1)/2 − ln J): μ, λm are vlab's; D = 2/K",
}
_U = {"quadratic": "(J − 1)²/D1", "simo-taylor": "(1/D)((J² − 1)/2 − ln J)"}


def _name(card: ExportCard) -> str:
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", card.name or "vlab")
    return name if name[:1].isalpha() else f"M{name}"


def _data(card: ExportCard, s: float) -> tuple[str, list[float]]:
    p, D = card.params, 2.0 / (card.K * s)
    if card.model == "mooney-rivlin":
        return "MOONEY-RIVLIN", [p["C10"] * s, p["C01"] * s, D]
    if card.model == "yeoh":
        return "REDUCED POLYNOMIAL, N=3", [p["C10"] * s, p["C20"] * s, p["C30"] * s, D, 0.0, 0.0]
    if card.model == "ogden":
        n = card.terms
        pairs = [v for m, a in zip(p["mu"], p["alpha"]) for v in (m * s, a)]
        return f"OGDEN, N={n}", pairs + [D] + [0.0] * (n - 1)
    return "ARRUDA-BOYCE", [p["mu"] * s, p["lambda_m"], D]


_PARTS = {"viscoelastic": "*VISCOELASTIC, TIME=PRONY (§22.7.1, Theory §4.8.2): gi = βi/(1 + Σβ), ki = 0, τi "
                         "(s); *HYPERELASTIC, MODULI=LONG TERM: the constants above are the long-term ones",
          "mullins": "*MULLINS EFFECT (§22.6.1): η = 1 − erf((Um − Ũdev)/(m + β Um))/r: r, m, β are vlab's"}


def write_deck(card: ExportCard, units, target: str, mappings: dict, manual: str) -> str:
    """The *MATERIAL block (module docstring), ``**`` comments on top."""
    m = mappings[card.model]
    option, values = _data(card, units.stress)
    if "viscoelastic" in card.parts:
        option += ", MODULI=LONG TERM"
    lines = header(card, target, f"*HYPERELASTIC, {option}", CONVENTION[card.model], units, manual,
                   _U[m.volumetric], tuple(_PARTS[p] for p in card.parts if p in _PARTS))
    out = commented(lines, "**") + f"*MATERIAL, NAME={_name(card)}\n*HYPERELASTIC, {option}\n"
    for i in range(0, len(values), 8):
        out += ", ".join(num(v) for v in values[i:i + 8]) + "\n"
    ve, mu = card.effects.get("viscoelastic"), card.effects.get("mullins")
    if ve:
        out += "*VISCOELASTIC, TIME=PRONY\n" + "".join(
            f"{num(g)}, {num(0.0)}, {num(t)}\n" for g, t in zip(normalised(ve["beta"]), ve["tau"]))
    if mu:
        out += f"*MULLINS EFFECT\n{num(mu['r'])}, {num(mu['m'] * units.stress)}, {num(mu['beta'])}\n"
    if card.density is not None:
        out += f"*DENSITY\n{num(card.density * units.density)}\n"
    return out


# --- reading ---------------------------------------------------------------------------------
_TYPES = {"NEO HOOKE": "neo", "MOONEY-RIVLIN": "mr", "YEOH": "yeoh", "REDUCED POLYNOMIAL": "rp",
          "OGDEN": "ogden", "ARRUDA-BOYCE": "ab"}


def _keywords(text: str, where: str):
    """[(line number, keyword, options, [(line, data fields)])] of the deck (comments dropped)."""
    blocks = []
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("**"):
            continue
        if line.startswith("*"):
            head, *opts = [x.strip() for x in line[1:].split(",")]
            blocks.append((n, head.upper(), [o for o in opts if o], []))
        elif blocks:
            blocks[-1][3].append((n, [x.strip() for x in line.rstrip(",").split(",")]))
        else:
            raise CardFormatError(f"{where}, line {n}: data line before any keyword: {raw.strip()!r}")
    return blocks


def _numbers(rows, where: str) -> list[float]:
    out = []
    for n, fields in rows:
        for f in fields:
            try:
                out.append(float(f.replace("D", "E").replace("d", "e")) if f else 0.0)
            except ValueError:
                raise CardFormatError(f"{where}, line {n}: {f!r} is not a number") from None
    return out


def _options(n: int, opts: list[str], where: str) -> tuple[str, int | None]:
    kind, N = None, None
    for o in opts:
        key, _, value = (x.strip().upper() for x in o.partition("="))
        if key in _TYPES and not value:
            kind = _TYPES[key]
        elif key == "N":
            try:
                N = int(value)
            except ValueError:
                raise CardFormatError(f"{where}, line {n}: *HYPERELASTIC N={value!r} is not an integer") from None
        elif key == "MODULI":
            if value != "LONG TERM":
                raise CardFormatError(f"{where}, line {n}: *HYPERELASTIC, MODULI={value}: vlab reads long-term "
                                      "constants only (MODULI=LONG TERM, Abaqus' default)")
        elif key == "TEST DATA INPUT":
            raise CardFormatError(f"{where}, line {n}: *HYPERELASTIC, TEST DATA INPUT gives test data, not "
                                  "coefficients; vlab reads the coefficients only (fit the data with vlab fit)")
        else:
            raise CardFormatError(f"{where}, line {n}: *HYPERELASTIC option {o!r} is not read by vlab (allowed: "
                                  f"{', '.join(_TYPES)}, N=, MODULI=)")
    if kind is None:
        raise CardFormatError(f"{where}, line {n}: *HYPERELASTIC names no model vlab reads (allowed: "
                              f"{', '.join(_TYPES)}; Abaqus' default POLYNOMIAL is not one)")
    return kind, N


def _expected(kind: str, N: int | None, n: int, where: str) -> int:
    if kind in ("rp", "ogden"):
        top = 3 if kind == "rp" else 6
        if N is None or not 1 <= N <= top:
            raise CardFormatError(f"{where}, line {n}: *HYPERELASTIC needs N = 1 … {top} here, got {N}")
    return {"neo": 2, "mr": 3, "yeoh": 6, "ab": 3, "rp": 2 * (N or 0), "ogden": 3 * (N or 0)}[kind]


def _card(kind: str, N: int | None, v: list[float], s: float, n: int, where: str) -> tuple[str, dict, str, float]:
    """(model, params, volumetric, D1) in vlab units."""
    if kind in ("neo", "mr"):
        return "mooney-rivlin", {"C10": v[0] / s, "C01": (v[1] if kind == "mr" else 0.0) / s}, "quadratic", v[-1]
    if kind in ("yeoh", "rp"):
        k = 3 if kind == "yeoh" else N
        c = [x / s for x in v[:k]] + [0.0] * (3 - k)
        _no_higher_D(v[k + 1:], n, where)
        return "yeoh", {"C10": c[0], "C20": c[1], "C30": c[2]}, "quadratic", v[k]
    if kind == "ogden":
        _no_higher_D(v[2 * N + 1:], n, where)
        return ("ogden", {"mu": tuple(x / s for x in v[0:2 * N:2]), "alpha": tuple(v[1:2 * N:2])},
                "quadratic", v[2 * N])
    return "arruda-boyce", {"mu": v[0] / s, "lambda_m": v[1]}, "simo-taylor", v[2]


def _no_higher_D(ds: list[float], n: int, where: str) -> None:
    if any(d != 0.0 for d in ds):
        raise CardFormatError(f"{where}, line {n}: D2, D3, … must be 0 (vlab's U(J) has one term), got "
                              f"{', '.join(f'{d:g}' for d in ds)}")


def read_deck(text: str, where: str, units) -> ExportCard:
    """The ExportCard of the first *HYPERELASTIC of a deck (module docstring)."""
    from vlab.export.card import card_from_table, material_table

    blocks = _keywords(text, where)
    hyper = [b for b in blocks if b[1] == "HYPERELASTIC"]
    if not hyper:
        raise CardFormatError(f"{where}: no *HYPERELASTIC keyword")
    n, _, opts, rows = hyper[0]
    kind, N = _options(n, opts, where)
    want = _expected(kind, N, n, where)
    values = _numbers(rows, where)
    if len(rows) == 0 or len(values) != want:
        raise CardFormatError(f"{where}, line {n}: *HYPERELASTIC {', '.join(opts)} needs {want} constants on its "
                              f"data lines, got {len(values)}")
    model, params, volumetric, D = _card(kind, N, values, units.stress, n, where)
    if not D > 0.0:
        raise CardFormatError(f"{where}, line {n}: D1 = {D:g}: vlab needs a compressible card (D1 > 0, K = 2/D1)")
    name = next((o.partition("=")[2].strip() for b in blocks if b[1] == "MATERIAL" for o in b[2]
                 if o.upper().startswith("NAME")), "vlab")
    dens = [b for b in blocks if b[1] == "DENSITY"]
    density = _numbers(dens[0][3], where)[0] / units.density if dens and dens[0][3] else None
    base = ExportCard(model, params, 2.0 / D / units.stress, volumetric, density)
    table = material_table(base)
    card = card_from_table(table, where, name=name, source=Source("import", where))
    try:
        return imported(with_parts(card, _parts(blocks, where, units), where), where, "abaqus")
    except ValueError as exc:
        raise CardFormatError(str(exc)) from None


def _parts(blocks, where: str, units) -> dict:
    """The [effects] tables of the deck's *VISCOELASTIC and *MULLINS EFFECT (module docstring)."""
    out = {}
    for n, key, opts, rows in blocks:
        if key not in ("VISCOELASTIC", "MULLINS EFFECT"):
            continue
        if key in out:
            raise CardFormatError(f"{where}, line {n}: a second *{key}")
        want = ["TIME=PRONY"] if key == "VISCOELASTIC" else ["DEFINITION=CONSTANTS"]
        bad = [o for o in opts if o.upper().replace(" ", "") not in want]
        if (key == "VISCOELASTIC" and [o.upper().replace(" ", "") for o in opts] != want) or bad:
            raise CardFormatError(f"{where}, line {n}: *{key} options {', '.join(opts) or '(none)'}: vlab reads "
                                  f"*{key}, {want[0]} only")
        values = [_numbers([r], where) for r in rows]
        if key == "VISCOELASTIC":
            out["viscoelastic"] = _prony(rows, values, n, where)
        else:
            if len(rows) != 1 or not 2 <= len(values[0]) <= 3:
                raise CardFormatError(f"{where}, line {n}: *MULLINS EFFECT needs one data line r, m[, β]")
            v = values[0] + [0.0] * (3 - len(values[0]))
            out["mullins"] = {"r": v[0], "m": v[1] / units.stress, "beta": v[2]}
    return {k: out[k] for k in ("viscoelastic", "mullins") if k in out}


def _prony(rows, values, n: int, where: str) -> dict:
    """{"tau", "beta"} of *VISCOELASTIC, TIME=PRONY data lines gᵢ, kᵢ, τᵢ (kᵢ = 0)."""
    if not rows:
        raise CardFormatError(f"{where}, line {n}: *VISCOELASTIC, TIME=PRONY has no data lines")
    for (line, _), v in zip(rows, values):
        if len(v) != 3:
            raise CardFormatError(f"{where}, line {line}: a Prony data line is g, k, tau (3 numbers), got {len(v)}")
        if v[1] != 0.0:
            raise CardFormatError(f"{where}, line {line}: k = {v[1]:g}: vlab's bulk modulus does not relax (k = 0)")
    g = [v[0] for v in values]
    if not sum(g) < 1.0:
        raise CardFormatError(f"{where}, line {n}: the Prony g sum to {sum(g):g}; Abaqus needs Σg < 1")
    return {"tau": [v[2] for v in values], "beta": list(relative(g))}


def write(card: ExportCard, units) -> str:
    return write_deck(card, units, "abaqus", MAPPINGS, _MANUAL)


def read(text: str, where: str, units) -> ExportCard:
    return read_deck(text, where, units)


ABAQUS = Exporter("abaqus", "abaqus.inp", "**", MAPPINGS, write, read, notes=NOTES, doc=__doc__,
                  parts=("hyperelastic", "viscoelastic", "mullins"), check_parts=lambda c: needs(c, "abaqus"))
