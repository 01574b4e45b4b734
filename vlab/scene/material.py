"""``[material]``: the model name, exactly two elastic constants (any two of E, nu, lambda,
mu/G, K, M; ``root`` picks the (E, M) root) and an optional density (kg/m³, stored in t/mm³).
The model registry of vlab.materials replaces ``MODELS`` here by delegation (issue 17).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vlab import fields
from vlab.fields import SceneError
from vlab.moduli import ALIASES, KEYS as MODULI_KEYS, Moduli, ModuliError, from_pair

__all__ = ["MaterialSpec", "MODELS", "SPRING_NETWORK", "KG_PER_M3", "parse_material"]


SPRING_NETWORK = "spring-network"  # not a material law: mesh edges as springs (vlab.fe.spring_network)


MODELS = ("linear", "stvk", "stvk-volumetric", "neo-hookean", SPRING_NETWORK)


_MODULI_NAMES = MODULI_KEYS + tuple(ALIASES)  # E, nu, lambda, mu, K, M, G, lmbda


KG_PER_M3 = 1e-12  # t/mm³: the mass unit of the N, mm, s system is the tonne (1 N = 1 t·mm/s²)


@dataclass(frozen=True)
class MaterialSpec:
    model: str
    moduli: Moduli
    given: dict[str, float]  # the two constants as given, canonical names (G -> mu)
    density: float | None = None  # t/mm³ (given in kg/m³: 1 kg/m³ = 1e-12 t/mm³); gravity needs it


def parse_material(raw: Any) -> MaterialSpec:
    t = fields.Table("material", raw, ("model", "root", "density") + _MODULI_NAMES)
    model = t.choice("model", MODELS)
    root = t.choice("root", ("plus", "minus"), default="plus")
    values = {k: t.number(k) for k in _MODULI_NAMES if k in t.raw}
    try:
        moduli = from_pair(values, root=root)
    except ModuliError as exc:
        msg = str(exc)
        raise SceneError(msg if "material." in msg
                         else f"[material]: {msg}") from None
    given = {ALIASES.get(k, k): v for k, v in values.items()}
    density = t.number("density", default=None, gt=0, le=30000, note=" kg/m³")
    return MaterialSpec(model=model, moduli=moduli, given=given,
                        density=None if density is None else density * KG_PER_M3)
