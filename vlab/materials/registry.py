"""The one list of material models: every layer that needs to know a model reads ``MODELS``.

Contract. A ``Model`` entry says, for the name a scene writes in ``material.model``:

- ``constants``: the card's constants, each a ``Constant`` (card key, unit, allowed range,
  scalar or list, default) — or ``None`` for the moduli grammar of the small-strain-parametrised
  models (any two of E, nu, lambda, mu/G, K, M; vlab.moduli). A model with constants also takes
  its bulk modulus as exactly one of K (MPa) | D1 (= 2/K, 1/MPa) | nu (with the model's μ0) and
  ``volumetric`` = "quadratic" | "log" | "simo-taylor" (vlab.materials.volumetric).
- ``build(card) -> law``: the one-field law (energy, stress, tangent on (3, 3, *batch) fields;
  vlab.materials.base) from a validated card (``MaterialCard``: model, moduli, params,
  volumetric); ``split(card) -> law`` the volumetric–isochoric law of the mixed formulation, or
  ``None`` if the model has no split (the scene then refuses mesh.formulation = "mixed").
- the law's ``mu0`` (``mu``), ``K`` (``bulk_modulus``) and small-strain ``youngs_modulus``,
  ``poisson_ratio``: vlab.materials.card turns them into the card's ``Moduli``, so the
  solver's scales, the locking warning and results.json (input.small_strain) read one place.
- ``continuum``: False for a model that is a body, not a law (the spring network: built by
  vlab.fe.spring_network from E alone; no sheets, effects, order 2 or mixed formulation).
- ``isochoric``: True if the law has an isochoric part ψ_iso(C̄) the viscoelastic branches
  (effects.viscoelastic) act on; ``hencky``: True if J2 plasticity's Hencky elastic part with
  the card's E, ν is this model's small-strain law (the moduli-grammar models).
- ``compiled``: how the tangent is assembled (the README's model table quotes it).
- ``formula``: ψ, as the README writes it.

The effects registry (``Effect.models``), the scene (card grammar, formulation and
spring-network checks), compare's model list and the CLI all ask this registry.

Adding a model: one file in vlab/materials/ with the law (for a split model subclass
vlab.materials.invariant.InvariantModel — W and its derivatives — or
vlab.materials.isochoric.IsochoricVolumetric), its tests, and one ``_register(Model(...))``
line below.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from vlab.materials.arruda_boyce import LAMBDA_M_MAX, ArrudaBoyce
from vlab.materials.gent import Gent
from vlab.materials.linear import LinearElastic
from vlab.materials.mooney_rivlin import MooneyRivlin
from vlab.materials.neo_hookean import NeoHookean
from vlab.materials.ogden import ALPHA_RANGE, Ogden
from vlab.materials.split import SplitLinear, SplitNeoHookean
from vlab.materials.stvk import StVenantKirchhoff
from vlab.materials.stvk_volumetric import StVKVolumetric
from vlab.materials.yeoh import Yeoh
from vlab.moduli import MODULUS_RANGE

__all__ = ["Constant", "Model", "MaterialCard", "MODELS", "register", "models_where", "model"]


@dataclass(frozen=True)
class Constant:
    """One card constant: key (as in the card), class field, unit, bounds, list or scalar."""

    key: str
    field: str
    unit: str
    doc: str
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    nonzero: bool = False          # αₚ ≠ 0
    is_list: bool = False          # a list of any length ≥ 1 (all lists of a card: equal length)
    default: float | None = None   # None: required
    le: float | None = None
    # lo <= |value| <= hi (0 is allowed where lo is 0): where double precision ends, the card's
    # terms under- or overflow (vlab.materials.card checks it, naming the key and the range)
    magnitude: tuple[float, float] = (0.0, float("inf"))

    def bounds(self) -> dict:
        pairs = (("gt", self.gt), ("ge", self.ge), ("lt", self.lt), ("le", self.le))
        return {k: v for k, v in pairs if v is not None}


@dataclass(frozen=True)
class MaterialCard:
    """A validated ``[material]`` card: model name, small-strain Moduli, constants, volumetric."""

    model: str
    moduli: Any
    params: dict = field(default_factory=dict)
    volumetric: str | None = None


@dataclass(frozen=True)
class Model:
    name: str
    formula: str
    build: Callable[[Any], Any]
    constants: tuple[Constant, ...] | None = None
    split: Callable[[Any], Any] | None = None
    continuum: bool = True
    isochoric: bool = False
    hencky: bool = False
    compiled: str = "numpy"
    mu0: str = "mu"

    @property
    def keys(self) -> tuple[str, ...]:
        """The card keys of the constants (None for the moduli grammar)."""
        return tuple(c.key for c in self.constants) if self.constants else ()


MODELS: dict[str, Model] = {}


def register(entry: Model) -> Model:
    MODELS[entry.name] = entry
    return entry


def model(name: str) -> Model:
    """The entry of ``material.model`` = name; ValueError naming the allowed models."""
    try:
        return MODELS[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown material.model {name!r}; allowed: {', '.join(MODELS)}") from None


def models_where(predicate: Callable[[Model], bool]) -> tuple[str, ...]:
    """The names of the registered models for which ``predicate(entry)`` holds."""
    return tuple(n for n, m in MODELS.items() if predicate(m))


def _lame(cls):
    return lambda card: cls(lmbda=card.moduli.lmbda, mu=card.moduli.mu)


def _split_card(cls):
    """build(card) for a split model: its constants as fields, plus K and the volumetric form."""
    def build(card):
        entry = MODELS[card.model]
        values = {c.field: card.params[c.key] for c in entry.constants}
        return cls(**values, K=card.moduli.K, volumetric=card.volumetric or "quadratic")
    return build


MPA, ONE = "MPa", "-"


def _C(key, field, unit, doc, **kw) -> Constant:
    """A Constant; an MPa constant's magnitude is bounded as the moduli are (MODULUS_RANGE's top:
    beyond it the forces and their squares overflow double precision; 0 stays allowed)."""
    if unit == MPA:
        kw.setdefault("magnitude", (0.0, MODULUS_RANGE[1]))
    return Constant(key, field, unit, doc, **kw)


register(Model("linear", "λ/2 (tr ε)² + μ ε:ε", _lame(LinearElastic), split=_lame(SplitLinear),
               hencky=True, compiled="compiled"))
register(Model("stvk", "λ/2 (tr E)² + μ E:E", _lame(StVenantKirchhoff), hencky=True, compiled="compiled"))
register(Model("stvk-volumetric", "λ/2 (J − 1)² + μ E:E", _lame(StVKVolumetric), hencky=True))
register(Model("neo-hookean", "μ/2 (I₁ − 3) − μ ln J + λ/2 ln²J", _lame(NeoHookean),
               split=_lame(SplitNeoHookean), isochoric=True, hencky=True, compiled="compiled"))
register(Model("spring-network", "Σ ½ k̃ ε² L over the mesh edges", build=lambda card: None,
               continuum=False))
register(Model("mooney-rivlin", "C10 (Ī₁ − 3) + C01 (Ī₂ − 3) + U(J)", _split_card(MooneyRivlin),
               (_C("C10", "C10", MPA, "coefficient of Ī₁ − 3"),
                _C("C01", "C01", MPA, "coefficient of Ī₂ − 3")),
               split=_split_card(MooneyRivlin), isochoric=True, mu0="2 (C10 + C01)"))
register(Model("yeoh", "Σᵢ Ci0 (Ī₁ − 3)^i, i = 1..3, + U(J)", _split_card(Yeoh),
               (_C("C10", "C10", MPA, "coefficient of Ī₁ − 3"),
                _C("C20", "C20", MPA, "coefficient of (Ī₁ − 3)²", default=0.0),
                _C("C30", "C30", MPA, "coefficient of (Ī₁ − 3)³", default=0.0)),
               split=_split_card(Yeoh), isochoric=True, mu0="2 C10"))
register(Model("ogden", "Σₚ 2μₚ/αₚ² (λ̄₁^αₚ + λ̄₂^αₚ + λ̄₃^αₚ − 3) + U(J)", _split_card(Ogden),
               (_C("mu", "mus", MPA, "μₚ, one per term", is_list=True),
                _C("alpha", "alphas", ONE, "αₚ, one per term", nonzero=True, is_list=True,
                   magnitude=ALPHA_RANGE)),
               split=_split_card(Ogden), isochoric=True, mu0="Σₚ μₚ"))
register(Model("gent", "−(μ Jm/2) ln(1 − (Ī₁ − 3)/Jm) + U(J)", _split_card(Gent),
               (_C("mu", "modulus", MPA, "shear modulus μ", gt=0.0),
                _C("Jm", "Jm", ONE, "locking limit of Ī₁ − 3", gt=0.0)),
               split=_split_card(Gent), isochoric=True, mu0="μ"))
register(Model("arruda-boyce", "μ Σᵢ Cᵢ/λm^(2i−2) (Ī₁^i − 3^i), i = 1..5, + U(J)", _split_card(ArrudaBoyce),
               (_C("mu", "modulus", MPA, "chain modulus μ", gt=0.0),
                _C("lambda_m", "lambda_m", ONE, "locking stretch λm", gt=1.0, le=LAMBDA_M_MAX)),
               split=_split_card(ArrudaBoyce), isochoric=True,
               mu0="μ (1 + 3/(5λm²) + 99/(175λm⁴) + 513/(875λm⁶) + 42039/(67375λm⁸))"))
