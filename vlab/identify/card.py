"""The [material] card of a fit, in the grammar `vlab run` reads (Abaqus names, MPa).

An incompressible fit has no bulk modulus of its own; the card then carries K = r μ0 with
r = ``[model] K_over_mu`` (default INCOMPRESSIBLE_K_RATIO = 1000, allowed 10..1e8), i.e.
ν = (3r − 2)/(6r + 2) (0.4995 at r = 1000), a stand-in for incompressibility that a finite-element
run needs, best used with ``[mesh] formulation = "mixed"``; the ratio is stated in the card's
comment, in its note and in fit.json → model.K_over_mu. A fixed or fitted K is written as is,
with the fit's volumetric energy when it is not the default quadratic one.
"""

from __future__ import annotations

from vlab.identify.states import Constitutive

__all__ = ["card_of", "card_toml", "INCOMPRESSIBLE_K_RATIO"]

INCOMPRESSIBLE_K_RATIO = 1000.0


def card_of(model: Constitutive, values, note: str | None = None) -> dict:
    """{"material": table, "toml": text, "note": why K is what it is (``note`` replaces it)}."""
    n = len(model.law.names)
    table = model.law.card(values[:n])
    mu0 = model.law.mu0(values[:n])
    if model.bulk == "incompressible":
        r = model.K_over_mu
        K, note_default = r * mu0, (f"incompressible fit: K = {r:g} mu0 (model.K_over_mu; nu = {poisson_of(r):.6g}) "
                            "stands in for incompressibility (use [mesh] formulation = \"mixed\")")
    else:
        K = float(values[n]) if model.bulk == "fit" else float(model.K)
        note_default = "K fitted" if model.bulk == "fit" else "K held fixed at the fit file's value"
    table["K"] = float(f"{K:.6g}")
    note = note or note_default
    if model.volumetric != "quadratic" and model.law.model != "neo-hookean":
        table["volumetric"] = model.volumetric
    return {"material": table, "toml": f"# {note}\n" + card_toml(table), "note": note}


def poisson_of(ratio: float) -> float:
    """Small-strain ν of K = ratio · μ0: ν = (3r − 2)/(6r + 2)."""
    return (3.0 * ratio - 2.0) / (6.0 * ratio + 2.0)


def _value(v) -> str:
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, str):
        return f'"{v}"'
    return repr(float(v))


def card_toml(table: dict) -> str:
    """The table as TOML text under [material]."""
    return "[material]\n" + "".join(f"{k} = {_value(v)}\n" for k, v in table.items())
