"""ANSYS Mechanical APDL ``TB,HYPER`` (Material Reference §4.6 "Hyperelastic Material
Constants": §4.6.1 BOYCE, §4.6.4 GENT, §4.6.6 MOONEY, §4.6.7 NEO, §4.6.8 OGDEN, §4.6.12 YEOH;
Command Reference TB, TBDATA, MP).

ANSYS writes W = W_iso(Ī₁, Ī₂ or λ̄ᵢ) + W_vol(J) with the incompressibility parameters d = 2/K:

- MOONEY (NPTS = 2): W = c10 (Ī₁ − 3) + c01 (Ī₂ − 3) + (J − 1)²/d         TBDATA c10, c01, d
- YEOH (NPTS = 3):   W = Σᵢ ci0 (Ī₁ − 3)^i + Σₖ (J − 1)^(2k)/dk           TBDATA c10, c20, c30, d1, d2, d3
- OGDEN (NPTS = N):  W = Σᵢ μᵢ/αᵢ (λ̄₁^αᵢ + λ̄₂^αᵢ + λ̄₃^αᵢ − 3) + Σₖ (J − 1)^(2k)/dk,
                     initial shear modulus ½ Σ μᵢ αᵢ                     TBDATA μ1, α1, …, μN, αN, d1, …, dN
- BOYCE:             W = μ Σᵢ Cᵢ/λL^(2i−2) (Ī₁^i − 3^i) + (1/d)((J² − 1)/2 − ln J)   TBDATA μ, λL, d
- GENT:              W = −(μ Jm/2) ln(1 − (Ī₁ − 3)/Jm) + (1/d)((J² − 1)/2 − ln J)    TBDATA μ, Jm, d
- NEO (read only):   W = μ/2 (Ī₁ − 3) + (J − 1)²/d                         TBDATA μ, d

Conversions: ANSYS' Ogden μᵢ is not vlab's: μᵢ/αᵢ = 2 μᵢ(vlab)/αᵢ², i.e. μᵢ(ANSYS) = 2 μᵢ(vlab)/αᵢ
(the shear modulus ½ Σ μᵢ αᵢ = Σ μᵢ(vlab) agrees); every other constant is vlab's own; d = 2/K with
d2 = d3 = … = 0; (J − 1)²/d is vlab's "quadratic" U, (1/d)((J² − 1)/2 − ln J) its "simo-taylor".
vlab's coupled neo-hookean has no ANSYS form (NEO is the split law: vlab's mooney-rivlin with
C01 = 0) and is refused. Material number 1; density as ``MP,DENS``.

Viscoelastic and Mullins parts (vlab.export.parts says when they are vlab's model: a
Neo-Hookean ground for the Prony part, an incompressible fit's card for both):

- ``TB,PRONY,1,1,N,SHEAR`` (Material Reference "Viscoelasticity", Prony series; Theory Reference
  §4.7 "Viscoelasticity", large-deformation form after Simo): the deviatoric second Piola–
  Kirchhoff stress of the hyperelastic law is relaxed with G(t)/G0 = α∞ + Σᵢ αᵢ e^(−t/τᵢ),
  α∞ = 1 − Σαᵢ, TBDATA α1, τ1, α2, τ2, …. The TB,HYPER constants of a viscoelastic material are
  its *instantaneous* (t = 0) response (the Material Reference's viscoelasticity chapter, as
  recalled: no stored copy of that sentence was found to re-read; docs/export.md says so), so vlab's long-term constants are written × (1 + Σβ)
  (= 1/α∞) and αᵢ = βᵢ/(1 + Σβ): the shear relaxation modulus is μ0 (1 + Σ βᵢ e^(−t/τᵢ)), τᵢ in
  s. No ``BULK`` table: vlab's bulk modulus does not relax (d is written as is).
- ``TB,CDM,1,1,3,PSE2`` (Material Reference "Mullins Effect", the modified Ogden–Roxburgh
  pseudo-elastic model): η = 1 − (1/r) erf((W_m − W_0)/(m + β W_m)), W_0 the virgin material's
  (deviatoric) strain energy and W_m its largest previous value; TBDATA r, m, β — vlab's r, m
  (MPa or Pa), β. "Modified" is the β W_m term of the scale; β = 0 is Ogden and Roxburgh's.
"""

from __future__ import annotations

from dataclasses import replace

from vlab.export.card import ExportCard, Source, with_parts
from vlab.export.header import commented, header, num
from vlab.export.parts import imported, needs, normalised, relative
from vlab.export.registry import CardFormatError, Exporter, Mapping

__all__ = ["ANSYS"]

_MANUAL = "ANSYS Mechanical APDL Material Reference §4.6 (TB,HYPER: 4.6.1 BOYCE, 4.6.4 GENT, 4.6.6 MOONEY, 4.6.8 OGDEN, 4.6.12 YEOH)"
MAPPINGS = {
    "mooney-rivlin": Mapping("TB,HYPER,,,2,MOONEY", "quadratic", "ANSYS Material Reference §4.6.6"),
    "yeoh": Mapping("TB,HYPER,,,3,YEOH", "quadratic", "ANSYS Material Reference §4.6.12"),
    "ogden": Mapping("TB,HYPER,,,N,OGDEN", "quadratic", "ANSYS Material Reference §4.6.8"),
    "arruda-boyce": Mapping("TB,HYPER,,,,BOYCE", "simo-taylor", "ANSYS Material Reference §4.6.1"),
    "gent": Mapping("TB,HYPER,,,,GENT", "simo-taylor", "ANSYS Material Reference §4.6.4"),
}
NOTES = {"neo-hookean": "ANSYS' NEO is the split μ/2 (Ī₁ − 3) + (J − 1)²/d; vlab's neo-hookean is coupled — "
                        "use model = \"mooney-rivlin\" with C01 = 0 for the split form"}
CONVENTION = {
    "mooney-rivlin": "W = c10 (Ī1 − 3) + c01 (Ī2 − 3) + (J − 1)²/d, d = 2/K",
    "yeoh": "W = Σ ci0 (Ī1 − 3)^i + Σ (J − 1)^(2k)/dk, d1 = 2/K, d2 = d3 = 0",
    "ogden": "W = Σ μi/αi (λ̄1^αi + λ̄2^αi + λ̄3^αi − 3) + Σ (J − 1)^(2k)/dk: μi(ANSYS) = 2 μi(vlab)/αi; d1 = 2/K, dk>1 = 0",
    "arruda-boyce": "W = μ Σ Ci/λL^(2i−2) (Ī1^i − 3^i) + (1/d)((J² − 1)/2 − ln J): μ, λL = λm are vlab's; d = 2/K",
    "gent": "W = −(μ Jm/2) ln(1 − (Ī1 − 3)/Jm) + (1/d)((J² − 1)/2 − ln J): μ, Jm are vlab's; d = 2/K",
}
_U = {"quadratic": "(J − 1)²/d", "simo-taylor": "(1/d)((J² − 1)/2 − ln J)"}


def _data(card: ExportCard, s: float) -> tuple[int | str, str, list[float]]:
    p, d = card.params, 2.0 / (card.K * s)
    if card.model == "mooney-rivlin":
        return 2, "MOONEY", [p["C10"] * s, p["C01"] * s, d]
    if card.model == "yeoh":
        return 3, "YEOH", [p["C10"] * s, p["C20"] * s, p["C30"] * s, d, 0.0, 0.0]
    if card.model == "ogden":
        n = card.terms
        pairs = [v for m, a in zip(p["mu"], p["alpha"]) for v in (2.0 * m * s / a, a)]
        return n, "OGDEN", pairs + [d] + [0.0] * (n - 1)
    if card.model == "arruda-boyce":
        return "", "BOYCE", [p["mu"] * s, p["lambda_m"], d]
    return "", "GENT", [p["mu"] * s, p["Jm"], d]


_ISOCHORIC = {"mooney-rivlin": ("C10", "C01"), "yeoh": ("C10", "C20", "C30"), "ogden": ("mu",)}
_PARTS = {"viscoelastic": "TB,PRONY,,,N,SHEAR (Material Reference, Prony series): αi = βi/(1 + Σβ), τi (s); the "
                          "TB,HYPER constants are the instantaneous ones: vlab's × (1 + Σβ), d as is",
          "mullins": "TB,CDM,,,3,PSE2 (Material Reference, Mullins effect): η = 1 − erf((Wm − W0)/(m + β Wm))/r: "
                     "r, m, β are vlab's"}


def _scaled(card: ExportCard, factor: float) -> ExportCard:
    """The card with its isochoric constants × factor (d, α unchanged)."""
    p = {k: (tuple(x * factor for x in v) if isinstance(v, tuple) else v * factor) if k in _ISOCHORIC[card.model]
         else v for k, v in card.params.items()}
    return replace(card, params=p)


def _tbdata(values: list[float]) -> str:
    return "".join(f"TBDATA,{i + 1}," + ",".join(num(v) for v in values[i:i + 6]) + "\n"
                   for i in range(0, len(values), 6))


def write(card: ExportCard, units) -> str:
    ve, mu = card.effects.get("viscoelastic"), card.effects.get("mullins")
    npts, opt, values = _data(_scaled(card, 1.0 + sum(ve["beta"])) if ve else card, units.stress)
    m = MAPPINGS[card.model]
    lines = header(card, "ansys", f"TB,HYPER,{opt}", CONVENTION[card.model], units, m.manual, _U[m.volumetric],
                   tuple(_PARTS[p] for p in card.parts if p in _PARTS))
    out = commented(lines, "!")
    if card.density is not None:
        out += f"MP,DENS,1,{num(card.density * units.density)}\n"
    out += f"TB,HYPER,1,1,{npts},{opt}\n" + _tbdata(values)
    if ve:
        pairs = [v for a, t in zip(normalised(ve["beta"]), ve["tau"]) for v in (a, t)]
        out += f"TB,PRONY,1,1,{len(ve['tau'])},SHEAR\n" + _tbdata(pairs)
    if mu:
        out += "TB,CDM,1,1,3,PSE2\n" + _tbdata([mu["r"], mu["m"] * units.stress, mu["beta"]])
    return out


# --- reading ---------------------------------------------------------------------------------
_OPTS = ("MOONEY", "YEOH", "OGDEN", "BOYCE", "GENT", "NEO")


def _float(text: str, n: int, where: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise CardFormatError(f"{where}, line {n}: {text!r} is not a number") from None


def _commands(text: str):
    for n, raw in enumerate(text.splitlines(), 1):
        line = raw.split("!", 1)[0].strip()
        if line:
            yield n, [f.strip() for f in line.split(",")]


def _table(text: str, where: str):
    """(line of TB, TBOPT, NPTS, {position: value}, density) of the first TB,HYPER, and
    {lab: the same} of the first TB,PRONY and TB,CDM."""
    tables, cur, density = {}, None, None
    for n, f in _commands(text):
        cmd = f[0].upper()
        if cmd == "TB":
            lab = f[1].upper() if len(f) > 1 else ""
            cur = lab if lab in ("HYPER", "PRONY", "CDM") and lab not in tables else None
            if cur is None:
                continue
            opt = f[5].upper() if len(f) > 5 else ""
            if lab == "HYPER" and opt not in _OPTS:
                raise CardFormatError(f"{where}, line {n}: TB,HYPER option {opt or '(none: MOONEY)'} is not read by "
                                      f"vlab (allowed: {', '.join(_OPTS)})")
            tables[lab] = (n, opt, f[4] if len(f) > 4 and f[4] else "", {})
        elif cmd == "TBDATA" and cur is not None:
            if len(f) < 3:
                raise CardFormatError(f"{where}, line {n}: TBDATA needs a start location and values")
            start = int(_float(f[1], n, where))
            for k, v in enumerate(f[2:]):
                if v:
                    tables[cur][3][start + k] = _float(v, n, where)
        elif cmd == "MP" and len(f) >= 4 and f[1].upper() == "DENS":
            density = _float(f[3], n, where)
    if "HYPER" not in tables:
        raise CardFormatError(f"{where}: no TB,HYPER command")
    n, opt, npts, data = tables.pop("HYPER")
    return (n, opt, npts), data, density, tables


def _parts(tables: dict, where: str, s: float) -> dict:
    """The [effects] tables of TB,PRONY (SHEAR) and TB,CDM (PSE2) (module docstring)."""
    out = {}
    if "PRONY" in tables:
        n, opt, npts, data = tables["PRONY"]
        if opt != "SHEAR":
            raise CardFormatError(f"{where}, line {n}: TB,PRONY option {opt or '(none)'}: vlab reads SHEAR only "
                                  "(its bulk modulus does not relax)")
        try:
            N = int(npts)
        except ValueError:
            raise CardFormatError(f"{where}, line {n}: TB,PRONY NPTS = {npts!r} is not an integer") from None
        if N < 1 or sorted(data) != list(range(1, 2 * N + 1)):
            raise CardFormatError(f"{where}, line {n}: TB,PRONY with NPTS = {N} needs α, τ at locations 1 … {2 * N}, "
                                  f"got {sorted(data)}")
        a = [data[2 * i + 1] for i in range(N)]
        if not sum(a) < 1.0:
            raise CardFormatError(f"{where}, line {n}: the Prony α sum to {sum(a):g}; ANSYS needs Σα < 1")
        out["viscoelastic"] = {"tau": [data[2 * i + 2] for i in range(N)], "beta": list(relative(a))}
    if "CDM" in tables:
        n, opt, npts, data = tables["CDM"]
        if opt != "PSE2" or sorted(data) != [1, 2, 3]:
            raise CardFormatError(f"{where}, line {n}: TB,CDM: vlab reads the modified Ogden–Roxburgh model "
                                  "(TBOPT = PSE2) with r, m, β at TBDATA locations 1 … 3")
        out["mullins"] = {"r": data[1], "m": data[2] / s, "beta": data[3]}
    return out


def _want(opt: str, npts: str, n: int, where: str) -> int:
    if opt in ("MOONEY", "YEOH", "OGDEN"):
        default = {"MOONEY": "2", "YEOH": "1", "OGDEN": "1"}[opt]
        try:
            N = int(npts or default)
        except ValueError:
            raise CardFormatError(f"{where}, line {n}: TB,HYPER NPTS = {npts!r} is not an integer") from None
        if opt == "MOONEY" and N != 2:
            raise CardFormatError(f"{where}, line {n}: MOONEY with NPTS = {N}: vlab reads the 2-parameter form only")
        if opt == "YEOH" and not 1 <= N <= 3:
            raise CardFormatError(f"{where}, line {n}: YEOH with NPTS = {N}: vlab's Yeoh has N ≤ 3")
        if N < 1:
            raise CardFormatError(f"{where}, line {n}: OGDEN needs NPTS ≥ 1, got {N}")
        return N
    return 0


def read(text: str, where: str, units) -> ExportCard:
    from vlab.export.card import card_from_table, material_table

    (n, opt, npts), data, density, tables = _table(text, where)
    N = _want(opt, npts, n, where)
    want = {"MOONEY": 3, "YEOH": 2 * N, "OGDEN": 3 * N, "BOYCE": 3, "GENT": 3, "NEO": 2}[opt]
    if sorted(data) != list(range(1, want + 1)):
        raise CardFormatError(f"{where}, line {n}: TB,HYPER,{opt} needs constants 1 … {want} on TBDATA, got "
                              f"{len(data)} at locations {sorted(data)}")
    v, s = [data[i] for i in range(1, want + 1)], units.stress
    higher = {"YEOH": v[N + 1:], "OGDEN": v[2 * N + 1:]}.get(opt, [])
    if any(x != 0.0 for x in higher):
        raise CardFormatError(f"{where}, line {n}: d2, d3, … must be 0 (vlab's U(J) has one term)")
    if opt in ("MOONEY", "NEO"):
        model, params, vol = "mooney-rivlin", {"C10": (v[0] if opt == "MOONEY" else v[0] / 2) / s,
                                               "C01": (v[1] / s if opt == "MOONEY" else 0.0)}, "quadratic"
    elif opt == "YEOH":
        c = [x / s for x in v[:N]] + [0.0] * (3 - N)
        model, params, vol = "yeoh", {"C10": c[0], "C20": c[1], "C30": c[2]}, "quadratic"
    elif opt == "OGDEN":
        mu_a, alpha = v[0:2 * N:2], v[1:2 * N:2]
        if any(a == 0.0 for a in alpha):
            raise CardFormatError(f"{where}, line {n}: an Ogden exponent α is 0")
        model, params, vol = "ogden", {"mu": tuple(m * a / 2.0 / s for m, a in zip(mu_a, alpha)),
                                       "alpha": tuple(alpha)}, "quadratic"
    elif opt == "BOYCE":
        model, params, vol = "arruda-boyce", {"mu": v[0] / s, "lambda_m": v[1]}, "simo-taylor"
    else:
        model, params, vol = "gent", {"mu": v[0] / s, "Jm": v[1]}, "simo-taylor"
    d = v[want - 1] if opt not in ("YEOH", "OGDEN") else v[N if opt == "YEOH" else 2 * N]
    if not d > 0.0:
        raise CardFormatError(f"{where}, line {n}: d = {d:g}: vlab needs a compressible card (d > 0, K = 2/d)")
    base = ExportCard(model, params, 2.0 / d / s, vol, None if density is None else density / units.density)
    parts = _parts(tables, where, s)
    if "viscoelastic" in parts:  # TB,HYPER holds the instantaneous response: back to vlab's long-term one
        if model not in _ISOCHORIC:
            raise CardFormatError(f"{where}, line {n}: TB,PRONY over TB,HYPER,{opt} is not vlab's viscoelastic model")
        base = _scaled(base, 1.0 / (1.0 + sum(parts["viscoelastic"]["beta"])))
    card = card_from_table(material_table(base), where, source=Source("import", where))
    try:
        return imported(with_parts(card, parts, where), where, "ansys")
    except ValueError as exc:
        raise CardFormatError(str(exc)) from None


ANSYS = Exporter("ansys", "ansys.mac", "!", MAPPINGS, write, read, notes=NOTES, doc=__doc__,
                 parts=("hyperelastic", "viscoelastic", "mullins"), check_parts=lambda c: needs(c, "ansys"))
