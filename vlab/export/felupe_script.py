"""FElupe: a Python file that runs as it is and defines ``umat``, a FElupe material of the whole
card (FElupe ≥ 9 with tensortrax; FElupe docs "Hyperelastic material models" and
felupe.constitution.tensortrax.models.hyperelastic).

FElupe's model functions take C and are the energies vlab writes, in vlab's own constants:

- ``fem.mooney_rivlin(C, C10, C01)``   ψ = C10 (Ī₁ − 3) + C01 (Ī₂ − 3)
- ``fem.yeoh(C, C10, C20, C30)``       ψ = Σ Ci0 (Ī₁ − 3)^i
- ``fem.ogden(C, mu, alpha)``          ψ = Σ 2μᵢ/αᵢ² (λ̄₁^αᵢ + λ̄₂^αᵢ + λ̄₃^αᵢ − 3); the file defines
  ``ogden`` as fem.ogden's own three lines with tensortrax' ``eigvalsh(C, eps=1e-13)``: its default
  perturbation √ε ≈ 1.5e-8 (which separates repeated eigenvalues) moves the stress of a uniaxial
  or equibiaxial state, where two stretches are equal, by up to 1e-4 relative (ogden-3, α = 5,
  −2); with 1e-13 the homogeneous states agree with vlab to 4e-10 and a general F to 1e-13;
- ``fem.arruda_boyce(C, C1, limit)``   ψ = C1 Σ Cᵢ/limit^(2i−2) (Ī₁^i − 3^i): C1 = μ, limit = λm
- Gent has no FElupe function: the file defines ``gent(C, mu, Jm)`` = −(μ Jm/2) ln(1 − (Ī₁ − 3)/Jm)
  with tensortrax' math, as FElupe's own functions are written;
- vlab's coupled neo-hookean is ``fem.NeoHookeCompressible(mu, lmbda)``
  (ψ = μ/2 tr C − μ ln J + λ/2 ln²J: vlab's up to the constant 3μ/2).

each wrapped in ``fem.Hyperelastic`` and joined (``&``) with the volumetric part:
``fem.Volumetric(bulk=K)`` (U = K/2 (J − 1)², vlab's "quadratic"), or for "log" and
"simo-taylor" a function of the file (``volumetric_log`` K/2 (ln J)², ``volumetric_simo_taylor``
K/4 (J² − 1 − 2 ln J)) in ``fem.Hyperelastic``. Every (model, volumetric) pair of vlab is written.

The reader does not execute the file: it reads the ``umat = …`` expression (ast) and takes the
literal constants of the calls above.
"""

from __future__ import annotations

import ast

from vlab.export.card import ExportCard, Source
from vlab.export.header import commented, header, num
from vlab.export.registry import CardFormatError, Exporter, Mapping

__all__ = ["FELUPE"]

_MANUAL = "FElupe documentation, hyperelastic material models (fem.Hyperelastic, fem.Volumetric)"
_ALL = ("quadratic", "log", "simo-taylor")
MAPPINGS = {m: Mapping(k, None, _MANUAL) for m, k in (
    ("mooney-rivlin", "fem.mooney_rivlin"), ("yeoh", "fem.yeoh"), ("ogden", "ogden (fem.ogden, eps = 1e-13)"),
    ("arruda-boyce", "fem.arruda_boyce"), ("gent", "gent"), ("neo-hookean", "fem.NeoHookeCompressible"))}
CONVENTION = "FElupe's functions of C with vlab's constants (C10, C01, Ci0, μi, αi, C1 = μ, limit = λm); + U(J) with bulk = K"

_FUNCS = {
    "ogden": ("def ogden(C, mu, alpha):\n"
              "    \"\"\"fem.ogden with eigvalsh(C, eps=1e-13): Σ 2μ/α² (λ̄1^α + λ̄2^α + λ̄3^α − 3).\"\"\"\n"
              "    wC = det(C) ** (-1 / 3) * eigvalsh(C, eps=1e-13)\n"
              "    return tsum([2 * m / a**2 * (tsum(wC ** (a / 2)) - 3) for m, a in zip(mu, alpha)])\n"),
    "gent": ("def gent(C, mu, Jm):\n"
             "    \"\"\"Gent: −(μ Jm/2) ln(1 − (Ī1 − 3)/Jm), Ī1 = J^(−2/3) tr C.\"\"\"\n"
             "    I1 = det(C) ** (-1 / 3) * trace(C)\n"
             "    return -mu * Jm / 2 * log(1 - (I1 - 3) / Jm)\n"),
    "log": ("def volumetric_log(C, bulk):\n"
            "    \"\"\"U = K/2 (ln J)², J = √det C.\"\"\"\n"
            "    lnJ = log(det(C)) / 2\n"
            "    return bulk / 2 * lnJ ** 2\n"),
    "simo-taylor": ("def volumetric_simo_taylor(C, bulk):\n"
                    "    \"\"\"U = K/4 (J² − 1 − 2 ln J), J² = det C.\"\"\"\n"
                    "    J2 = det(C)\n"
                    "    return bulk / 4 * (J2 - 1 - log(J2))\n"),
}


def _list(values, s: float = 1.0) -> str:
    return "[" + ", ".join(num(v * s) for v in values) + "]"


def _isochoric(card: ExportCard, s: float) -> str:
    p = card.params
    if card.model == "mooney-rivlin":
        return f"fem.Hyperelastic(fem.mooney_rivlin, C10={num(p['C10'] * s)}, C01={num(p['C01'] * s)})"
    if card.model == "yeoh":
        return (f"fem.Hyperelastic(fem.yeoh, C10={num(p['C10'] * s)}, C20={num(p['C20'] * s)}, "
                f"C30={num(p['C30'] * s)})")
    if card.model == "ogden":
        return f"fem.Hyperelastic(ogden, mu={_list(p['mu'], s)}, alpha={_list(p['alpha'])})"
    if card.model == "arruda-boyce":
        return f"fem.Hyperelastic(fem.arruda_boyce, C1={num(p['mu'] * s)}, limit={num(p['lambda_m'])})"
    return f"fem.Hyperelastic(gent, mu={num(p['mu'] * s)}, Jm={num(p['Jm'])})"


def write(card: ExportCard, units) -> str:
    s = units.stress
    u = {"quadratic": "K/2 (J − 1)²", "log": "K/2 (ln J)²", "simo-taylor": "K/4 (J² − 1 − 2 ln J)"}
    lines = header(card, "felupe", MAPPINGS[card.model].keyword, CONVENTION, units, _MANUAL,
                   u.get(card.volumetric))
    lines.append("use: umat = runpy.run_path(\"felupe.py\")[\"umat\"]; a file named felupe.py next to a script "
                 "shadows the felupe package, so rename it to import it")
    out = commented(lines, "#") + "import felupe as fem\n"
    if card.model == "neo-hookean":
        p = card.params
        return out + f"\numat = fem.NeoHookeCompressible(mu={num(p['mu'] * s)}, lmbda={num(p['lambda'] * s)})\n" \
            + _density(card, units)
    funcs = [_FUNCS[k] for k in (card.model, card.volumetric) if k in _FUNCS]
    if funcs:
        out += ("from tensortrax.math import log, trace\nfrom tensortrax.math import sum as tsum\n"
                "from tensortrax.math.linalg import det, eigvalsh\n")
        out += "".join("\n\n" + f for f in funcs)
    K = num(card.K * s)
    vol = (f"fem.Volumetric(bulk={K})" if card.volumetric == "quadratic" else
           f"fem.Hyperelastic(volumetric_{card.volumetric.replace('-', '_')}, bulk={K})")
    return out + f"\n\numat = {_isochoric(card, s)} & {vol}\n" + _density(card, units)


def _density(card: ExportCard, units) -> str:
    return "" if card.density is None else f"density = {num(card.density * units.density)}  # not part of umat\n"


# --- reading ---------------------------------------------------------------------------------
def _calls(node, where: str) -> list[ast.Call]:
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.BitAnd):
        return _calls(node.left, where) + _calls(node.right, where)
    if isinstance(node, ast.Call):
        return [node]
    raise CardFormatError(f"{where}, line {node.lineno}: umat must be FElupe materials joined by &")


def _name(node) -> str:
    return ast.unparse(node)


def _kwargs(call: ast.Call, where: str) -> dict:
    try:
        return {k.arg: ast.literal_eval(k.value) for k in call.keywords}
    except ValueError:
        raise CardFormatError(f"{where}, line {call.lineno}: the constants of {_name(call.func)} must be "
                              "numbers written in the file") from None


_ISO = {"fem.mooney_rivlin": ("mooney-rivlin", ("C10", "C01")), "fem.yeoh": ("yeoh", ("C10", "C20", "C30")),
        "fem.ogden": ("ogden", ("mu", "alpha")), "ogden": ("ogden", ("mu", "alpha")), "fem.arruda_boyce": ("arruda-boyce", ("C1", "limit")),
        "gent": ("gent", ("mu", "Jm"))}
_VOL = {"volumetric_log": "log", "volumetric_simo_taylor": "simo-taylor"}


def _assigned(tree, where: str):
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "umat" for t in node.targets):
            return node.value
    raise CardFormatError(f"{where}: no 'umat = …' assignment")


def _numbers(kw: dict, keys, line: int, where: str, name: str) -> dict:
    if sorted(kw) != sorted(keys):
        raise CardFormatError(f"{where}, line {line}: {name} needs {', '.join(keys)}, got {', '.join(kw) or 'none'}")
    for k, v in kw.items():
        vals = v if isinstance(v, (list, tuple)) else [v]
        if not vals or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in vals):
            raise CardFormatError(f"{where}, line {line}: {name} {k} = {v!r} is not a number (or list of numbers)")
    return kw


def read(text: str, where: str, units) -> ExportCard:
    from vlab.export.card import card_from_table, material_table

    try:
        tree = ast.parse(text)
    except SyntaxError as exc:
        raise CardFormatError(f"{where}, line {exc.lineno}: not valid Python ({exc.msg})") from None
    calls, s = _calls(_assigned(tree, where), where), units.stress
    model = params = K = vol = None
    for call in calls:
        f, kw = _name(call.func), _kwargs(call, where)
        if f == "fem.NeoHookeCompressible":
            kw = _numbers(kw, ("mu", "lmbda"), call.lineno, where, f)
            model, params = "neo-hookean", {"mu": kw["mu"] / s, "lambda": kw["lmbda"] / s}
        elif f == "fem.Volumetric":
            K, vol = _numbers(kw, ("bulk",), call.lineno, where, f)["bulk"] / s, "quadratic"
        elif f == "fem.Hyperelastic" and call.args:
            fn = _name(call.args[0])
            if fn in _VOL:
                K, vol = _numbers(kw, ("bulk",), call.lineno, where, fn)["bulk"] / s, _VOL[fn]
            elif fn in _ISO:
                model, keys = _ISO[fn]
                kw = _numbers(kw, keys, call.lineno, where, fn)
                params = _iso_params(model, kw, s, f"{where}, line {call.lineno}")
            else:
                raise CardFormatError(f"{where}, line {call.lineno}: {fn} is not read by vlab (allowed: "
                                      f"{', '.join(list(_ISO) + list(_VOL))})")
        else:
            raise CardFormatError(f"{where}, line {call.lineno}: {f} is not read by vlab")
    if model is None or (model != "neo-hookean" and K is None):
        raise CardFormatError(f"{where}: umat needs an isochoric model and a volumetric part")
    base = ExportCard(model, params, K, vol, _read_density(tree, where, units))
    return card_from_table(material_table(base), where, source=Source("import", where))


def _read_density(tree, where: str, units) -> float | None:
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "density" for t in node.targets):
            try:
                return float(ast.literal_eval(node.value)) / units.density
            except (ValueError, TypeError):
                raise CardFormatError(f"{where}, line {node.lineno}: density must be a number") from None
    return None


def _iso_params(model: str, kw: dict, s: float, where: str) -> dict:
    if model == "ogden":
        if not isinstance(kw["mu"], (list, tuple)) or not isinstance(kw["alpha"], (list, tuple)):
            raise CardFormatError(f"{where}: fem.ogden takes lists mu and alpha")
        if len(kw["mu"]) != len(kw["alpha"]):
            raise CardFormatError(f"{where}: fem.ogden mu and alpha need the same length, got {len(kw['mu'])} and {len(kw['alpha'])}")
        return {"mu": tuple(m / s for m in kw["mu"]), "alpha": tuple(kw["alpha"])}
    if model == "arruda-boyce":
        return {"mu": kw["C1"] / s, "lambda_m": kw["limit"]}
    if model == "gent":
        return {"mu": kw["mu"] / s, "Jm": kw["Jm"]}
    return {k: v / s for k, v in kw.items()}


FELUPE = Exporter("felupe", "felupe.py", "#", MAPPINGS, write, read, doc=__doc__)
