"""The viscoelastic (Prony) and Mullins (Ogden–Roxburgh) parts of an exported card, and when a
target's own part is vlab's model.

vlab's parts (vlab.materials.viscoelastic, vlab.materials.mullins):

- Prony: S = S∞(C) + Σᵢ Qᵢ, Q̇ᵢ + Qᵢ/τᵢ = βᵢ Ṡ_iso, with S_iso = F⁻¹ dev(μ0 b̄) F⁻ᵀ the isochoric
  Neo-Hookean stress of the ground law's initial shear modulus μ0 (MPa), τᵢ in s, βᵢ ≥ 0
  relative to the long-term modulus. Shear relaxation modulus μ(t) = μ0 (1 + Σᵢ βᵢ e^(−t/τᵢ));
  the bulk modulus does not relax.
- Mullins: P = η P0, η = 1 − erf((W_max − ψ0)/(m + β W_max))/r, ψ0 the ground law's whole energy
  (MPa), W_max its largest value so far; r > 1, m > 0 (MPa), β ≥ 0.

The targets' parts (Abaqus *VISCOELASTIC / *MULLINS EFFECT, ANSYS TB,PRONY / TB,CDM PSE2, FEBio
"uncoupled viscoelastic") relax or soften the ground law's *own* deviatoric stress and energy.
They are vlab's model exactly when

1. the ground law's deviatoric stress is the Neo-Hookean one of μ0 (for the Prony part): its
   isochoric energy is μ0/2 (Ī₁ − 3) — mooney-rivlin with C01 = 0, yeoh with C20 = C30 = 0,
   Ogden with every αᵢ = 2 (μ0 = Σ μᵢ), or an incompressible fit of neo-hookean, which is written
   in that split form (``split_neo_hookean``: at J = 1 vlab's coupled μ/2 (I₁ − 3) − μ ln J +
   λ/2 ln²J is μ/2 (Ī₁ − 3));
2. J = 1 where the target works on the deviatoric part only (Abaqus, ANSYS): vlab's Mullins
   factor multiplies the volumetric stress too and is driven by ψ0 with U(J), and vlab's Maxwell
   stress F Q Fᵀ is not traceless; so only an incompressible fit's card (its K a stand-in) is
   written to them. FEBio's uncoupled viscoelastic pulls back the same deviatoric Kirchhoff stress
   and pushes the history forward without projection (FEUncoupledViscoElasticMaterial::DevStress),
   so it is vlab's at any J.

Every other case is refused (vlab.export.registry), naming the targets that write the card.
"""

from __future__ import annotations

from dataclasses import replace

from vlab.fields import SceneError, Table

__all__ = ["PART_KEYS", "parse_parts", "neo_hookean_ground", "split_neo_hookean", "normalised", "relative",
           "needs", "prony_lines", "imported"]

PART_KEYS = {"viscoelastic": ("tau", "beta"), "mullins": ("r", "m", "beta")}


def parse_parts(effects: dict | None, where: str) -> dict:
    """{"viscoelastic": {"tau": (s, …), "beta": (…)}, "mullins": {"r", "m" (MPa), "beta"}} of a
    card's [effects] tables, validated by the scene grammar's own parsers (vlab.effects.viscoelastic,
    vlab.effects.mullins: the same keys, ranges and messages); other effects are not material
    parts and are ignored. A SceneError names ``where`` and the key."""
    from vlab.effects.mullins import parse_params
    from vlab.effects.viscoelastic import parse as parse_prony

    out = {}
    try:
        if (effects or {}).get("viscoelastic") is not None:
            spec = parse_prony(Table("effects.viscoelastic", effects["viscoelastic"], PART_KEYS["viscoelastic"]),
                               None, None)
            out["viscoelastic"] = {"tau": spec.tau, "beta": spec.beta}
        if (effects or {}).get("mullins") is not None:
            law = parse_params(effects["mullins"], "effects.mullins", None)  # the ground law is the card's
            out["mullins"] = {"r": law.r, "m": law.m, "beta": law.beta}
    except ValueError as exc:  # a SceneError, or the law's own check
        raise SceneError(f"{where}: {exc}") from None
    return out


def neo_hookean_ground(card) -> bool:
    """True if the card's isochoric energy is μ0/2 (Ī₁ − 3) (module docstring, condition 1)."""
    p = card.params
    if card.model == "mooney-rivlin":
        return p.get("C01") == 0.0
    if card.model == "yeoh":
        return p.get("C20") == 0.0 and p.get("C30") == 0.0
    if card.model == "ogden":
        return all(a == 2.0 for a in p["alpha"])
    return False


def split_neo_hookean(card):
    """An incompressible neo-hookean fit's card in the split form every target has:
    mooney-rivlin C10 = μ/2, C01 = 0, the same stand-in K (the same model at J = 1)."""
    p = card.params
    K = p["lambda"] + 2.0 * p["mu"] / 3.0
    return replace(card, model="mooney-rivlin", params={"C10": 0.5 * p["mu"], "C01": 0.0}, K=K,
                   volumetric="quadratic",
                   form="vlab's incompressible neo-hookean fit μ/2 (I1 − 3) written as the split "
                        "C10 (Ī1 − 3), C10 = μ/2, C01 = 0: the same model at J = 1")


def normalised(beta) -> tuple[float, ...]:
    """gᵢ = βᵢ/(1 + Σβ): the Prony weights relative to the instantaneous modulus."""
    total = 1.0 + sum(beta)
    return tuple(b / total for b in beta)


def relative(g) -> tuple[float, ...]:
    """βᵢ = gᵢ/(1 − Σg), the inverse of ``normalised`` (needs Σg < 1)."""
    rest = 1.0 - sum(g)
    return tuple(x / rest for x in g)


def needs(card, target: str, max_terms: int | None = None, any_J: tuple[str, ...] = ()) -> str | None:
    """Why ``target`` cannot carry the card's parts as vlab's model (module docstring), or None.
    ``any_J``: the parts the target has at every J (its construction is vlab's, not deviatoric only)."""
    parts = [p for p in card.parts if p in PART_KEYS]
    if not parts:
        return None
    if len(parts) > 1:
        return ("the card has both a viscoelastic and a Mullins part: vlab softens the long-term response and "
                "not the Maxwell branches, and no target documents its combination as that model")
    part = parts[0]
    if part == "viscoelastic":
        n = len(card.effects["viscoelastic"]["tau"])
        if max_terms is not None and n > max_terms:
            return f"{target} takes at most {max_terms} Prony terms, the card has {n}"
        if not neo_hookean_ground(card):
            return (f"{target} relaxes the ground law's own deviatoric stress, vlab's Maxwell branches are "
                    f"Neo-Hookean of μ0 whatever the ground law: the same model only for a Neo-Hookean ground "
                    f"(mooney-rivlin with C01 = 0, yeoh with C20 = C30 = 0, Ogden with every α = 2, or an "
                    f"incompressible neo-hookean fit), not this {card.describe()}")
    if part not in any_J and not card.stand_in:
        return (f"{target}'s {part} part acts on the deviatoric part only, vlab's on the whole stress: the same "
                "model at J = 1 only, so only an incompressible fit's card (its K a stand-in) is written")
    return None


def imported(card, where: str, target: str, any_J: tuple[str, ...] = ()):
    """A card read from ``target``'s file with its parts: refused (ValueError naming ``where``) when
    its Prony part is not vlab's model at any J (a ground law other than Neo-Hookean), and noted
    (the card's source note) when a part is vlab's model at J = 1 only."""
    from dataclasses import replace as _replace

    parts = [p for p in card.parts if p in PART_KEYS]
    if "viscoelastic" in parts and not neo_hookean_ground(card):
        raise ValueError(f"{where}: {target}'s Prony series relaxes this {card.model} ground law's own deviatoric "
                         "stress; vlab's viscoelastic effect has Neo-Hookean branches of μ0, the same model only for "
                         "a Neo-Hookean ground (C01 = 0, C20 = C30 = 0, Ogden α = 2)")
    at_one = [p for p in parts if p not in any_J]
    if not at_one:
        return card
    note = (f"{target}'s {' and '.join(at_one)} part acts on the deviatoric part only, vlab's on the whole stress: "
            "the same model at J = 1 (incompressible; use [mesh] formulation = \"mixed\")")
    return _replace(card, source=_replace(card.source, note=note) if card.source else card.source)


def prony_lines(card) -> list[str]:
    """The header lines of the parts, in vlab's names."""
    out = []
    ve, mu = card.effects.get("viscoelastic"), card.effects.get("mullins")
    if ve:
        out.append("viscoelastic (vlab): μ(t) = μ0 (1 + Σ βi exp(−t/τi)), τ = "
                   + ", ".join(f"{t:.6g}" for t in ve["tau"]) + " s, β = " + ", ".join(f"{b:.6g}" for b in ve["beta"]))
    if mu:
        out.append(f"mullins (vlab): η = 1 − erf((Wmax − ψ0)/(m + β Wmax))/r, r = {mu['r']:.6g}, "
                   f"m = {mu['m']:.6g} MPa, β = {mu['beta']:.6g}")
    return out
