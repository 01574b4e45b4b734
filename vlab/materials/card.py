"""A ``[material]`` table (a material card) -> a validated ``MaterialSpec``.

The grammar comes from the model registry (vlab.materials.registry): a model with
``constants`` takes exactly those keys (lists of equal length where the model has lists), the
bulk modulus as exactly one of K | D1 (= 2/K) | nu (with the model's μ0) and an optional
``volumetric``; the older models take any two of E, nu, lambda, mu/G, K, M (and ``root``). Both
take ``density`` (kg/m³). Every error is a SceneError naming ``<section>.<key>``, its allowed
range and what was got; a card whose initial tangent A(I) is not positive definite on symmetric
strains (shear 2μ0, bulk 3K) is refused with the eigenvalue that fails.

``check_path(spec, kind, test, specimen)`` refuses a test whose isochoric (incompressible) path passes a
model's locking limit (Gent: Ī₁ − 3 → Jm), naming the limit and the stretch where it is reached.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vlab import fields
from vlab.fields import SceneError
from vlab.materials.registry import MODELS, Model
from vlab.materials.volumetric import VOLUMETRIC_NAMES
from vlab.moduli import ALIASES, KEYS as MODULI_KEYS, MODULUS_RANGE, Moduli, ModuliError, from_pair

__all__ = ["MaterialSpec", "parse_material", "build_material", "build_split_law", "check_path",
           "BULK_KEYS"]

KG_PER_M3 = 1e-12  # t/mm³: the mass unit of the N, mm, s system is the tonne
BULK_KEYS = ("K", "D1", "nu")
_MODULI_NAMES = MODULI_KEYS + tuple(ALIASES)  # E, nu, lambda, mu, K, M, G, lmbda


@dataclass(frozen=True)
class MaterialSpec:
    model: str
    moduli: Moduli                       # small-strain constants (for a card: from μ0 and K)
    given: dict[str, float]              # the constants as given, canonical names (G -> mu)
    density: float | None = None         # t/mm³ (given in kg/m³); gravity needs it
    params: dict = field(default_factory=dict)  # the card's model constants (lists as tuples)
    volumetric: str | None = None        # U(J) of a card model (None for the moduli grammar)


def parse_material(raw: Any, section: str = "material") -> MaterialSpec:
    """Validate one material card (module docstring)."""
    if not isinstance(raw, dict):
        raise SceneError(f"[{section}] must be a table, got {fields.show(raw)}")
    if "model" not in raw:
        raise SceneError(f"missing required key {section}.model (allowed: {', '.join(MODELS)})")
    entry = MODELS[fields.choice(f"{section}.model", raw["model"], tuple(MODELS))]
    if entry.constants is None:
        return _parse_pair(raw, section, entry)
    return _parse_card(raw, section, entry)


def _density(t: fields.Table) -> float | None:
    density = t.number("density", default=None, gt=0, le=30000, note=" kg/m³")
    return None if density is None else density * KG_PER_M3


def _parse_pair(raw: dict, section: str, entry: Model) -> MaterialSpec:
    t = fields.Table(section, raw, ("model", "root", "density") + _MODULI_NAMES)
    root = t.choice("root", ("plus", "minus"), default="plus")
    values = {k: t.number(k) for k in _MODULI_NAMES if k in t.raw}
    try:
        moduli = from_pair(values, root=root)
    except ModuliError as exc:
        msg = str(exc) if section == "material" else str(exc).replace("material.", f"{section}.")
        raise SceneError(msg if f"{section}." in msg else f"[{section}]: {msg}") from None
    given = {ALIASES.get(k, k): v for k, v in values.items()}
    return MaterialSpec(model=entry.name, moduli=moduli, given=given, density=_density(t))


def _constant(t: fields.Table, c) -> float | tuple[float, ...]:
    note = f" ({c.unit}, {c.doc})"
    if not c.is_list:
        value = t.number(c.key, **({} if c.default is None else {"default": c.default}), **c.bounds(), note=note)
        values = (value,)
    else:
        raw = t.get(c.key)
        if isinstance(raw, (int, float)) and not isinstance(raw, bool):
            raw = [raw]
        if not isinstance(raw, list) or not raw:
            raise SceneError(f"{t.field(c.key)} must be a list of numbers{note}, got {fields.show(raw)}")
        values = tuple(fields.number(f"{t.field(c.key)}[{i}]", v, **c.bounds(), note=note)
                       for i, v in enumerate(raw))
    for i, v in enumerate(values):
        where = f"{t.field(c.key)}[{i}]" if c.is_list else t.field(c.key)
        if c.nonzero and v == 0.0:
            raise SceneError(f"{where} must be != 0{note}, got 0")
        _check_magnitude(where, v, c.magnitude, note)
    return values if c.is_list else values[0]


def _check_magnitude(where: str, v: float, magnitude: tuple[float, float], note: str) -> None:
    """lo <= |v| <= hi (v = 0 passes where lo = 0): the range where the card's terms stay in double
    precision (vlab.materials.registry.Constant.magnitude)."""
    lo, hi = magnitude
    if not lo <= abs(v) <= hi:
        rng = f"|{where}| <= {hi:g}" if lo == 0 else f"{lo:g} <= |{where}| <= {hi:g}"
        raise SceneError(f"{where} = {v:g} is outside the allowed range {rng}{note}: beyond it the card's "
                         "terms under- or overflow double precision")


def _check_scale(section: str, name: str, value: float, origin: str) -> None:
    """A derived modulus (the card's μ0, its K) within MODULUS_RANGE, MPa, as the moduli are:
    named here, before a solid of μ0 = 4e300 is misreported as nu = -1 (vlab.moduli)."""
    lo, hi = MODULUS_RANGE
    if not lo <= abs(value) <= hi:
        raise SceneError(f"[{section}]: {name} = {value:g} MPa (from {origin}) is outside the allowed range "
                         f"{lo:g}..{hi:g} MPa: beyond it the solver's forces and their squares under- or "
                         "overflow double precision")


def _parse_card(raw: dict, section: str, entry: Model) -> MaterialSpec:
    t = fields.Table(section, raw, ("model", "density", "volumetric") + entry.keys + BULK_KEYS)
    params = {c.key: _constant(t, c) for c in entry.constants}
    lists = {c.key: len(params[c.key]) for c in entry.constants if c.is_list}
    if len(set(lists.values())) > 1:
        got = ", ".join(f"{section}.{k} has {n}" for k, n in lists.items())
        raise SceneError(f"{section}: the lists {', '.join(lists)} need equal lengths (one entry per "
                         f"term), got {got}")
    volumetric = t.choice("volumetric", VOLUMETRIC_NAMES, default=VOLUMETRIC_NAMES[0])
    probe = _law(entry, section, params, K=1.0, volumetric=volumetric)
    _check_scale(section, "mu0", probe.mu0, " and ".join(f"{section}.{k}" for k in entry.keys))
    K, given_bulk = _bulk(t, probe.mu0)
    _check_scale(section, "the bulk modulus K", K, f"{section}.{next(iter(given_bulk))}")
    law = _law(entry, section, params, K=K, volumetric=volumetric)
    _check_initial_tangent(law, section, entry)
    try:
        moduli = from_pair({"mu": law.mu0, "K": K})
    except ModuliError as exc:
        raise SceneError(f"[{section}]: {exc}") from None
    return MaterialSpec(model=entry.name, moduli=moduli, given=given_bulk, density=_density(t),
                        params=params, volumetric=volumetric)


def _law(entry: Model, section: str, params: dict, K: float, volumetric: str):
    from vlab.materials.isochoric import NonPositiveShear
    from vlab.materials.registry import MaterialCard

    try:
        return entry.build(MaterialCard(entry.name, _BulkOnly(K), params, volumetric))
    except NonPositiveShear as exc:
        keys = " and ".join(f"{section}.{k}" for k in entry.keys)
        raise SceneError(f"{section}: the initial shear modulus mu0 = {entry.mu0} must be > 0 "
                         f"(MPa; from {keys}), got {exc.mu0:g}") from None
    except ValueError as exc:
        raise SceneError(f"[{section}]: {exc}") from None


@dataclass(frozen=True)
class _BulkOnly:
    K: float


def _bulk(t: fields.Table, mu0: float) -> tuple[float, dict]:
    """K from exactly one of K | D1 | nu (ν with the card's μ0), and the bulk key as given."""
    given = [k for k in BULK_KEYS if k in t.raw]
    if len(given) != 1:
        raise SceneError(f"[{t.section}] needs exactly one of {t.section}.K (MPa), {t.section}.D1 "
                         f"(= 2/K, 1/MPa) or {t.section}.nu (-1 < nu < 0.5, with mu0 = {mu0:g} MPa) "
                         f"for the volumetric part, got {', '.join(given) or 'none'}")
    key = given[0]
    if key == "K":
        K = t.number("K", gt=0, note=" (MPa, bulk modulus)")
    elif key == "D1":
        K = 2.0 / t.number("D1", gt=0, note=" (1/MPa, D1 = 2/K)")
    else:
        nu = t.number("nu", gt=-1.0, lt=0.5, note=" (Poisson's ratio; K = 2 mu0 (1 + nu)/(3 (1 - 2 nu)))")
        K = 2.0 * mu0 * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu))
    if not math.isfinite(K):
        raise SceneError(f"{t.field(key)} gives a bulk modulus K = {K} that is not finite")
    return K, {key: float(t.raw[key])}


def _check_initial_tangent(law, section: str, entry: Model) -> None:
    """A(I) must be positive definite on symmetric strains: eigenvalues 2μ0 (×5) and 3K."""
    A = np.asarray(law.tangent(np.eye(3)[..., None]))[..., 0].reshape(9, 9)
    basis = []
    for i in range(3):
        for j in range(i, 3):
            e = np.zeros((3, 3))
            e[i, j] = e[j, i] = 1.0 / (math.sqrt(2.0) if i != j else 1.0)
            basis.append(e.reshape(9))
    B = np.array(basis)
    eig = np.linalg.eigvalsh(B @ (0.5 * (A + A.T)) @ B.T)
    if not (np.all(np.isfinite(eig)) and eig.min() > 0.0):
        raise SceneError(f"[{section}]: the card's initial tangent is not positive definite on "
                         f"symmetric strains (smallest eigenvalue {eig.min():.6g} MPa; a stable card "
                         f"needs shear 2 mu0 > 0 and bulk 3K > 0 with mu0 = {entry.mu0})")


def build_material(spec) -> Any:
    """The one-field law of a MaterialSpec (registry ``build``)."""
    return MODELS[spec.model].build(spec)


def build_split_law(spec) -> Any:
    """The split law of a MaterialSpec for mesh.formulation = "mixed"; ValueError if none."""
    split = MODELS[spec.model].split
    if split is None:
        allowed = ", ".join(n for n, m in MODELS.items() if m.split is not None)
        raise ValueError(f"mesh.formulation = 'mixed' needs a volumetric–isochoric split; "
                         f"material.model {spec.model!r} has none (allowed: {allowed})")
    return split(spec)


def check_path(spec, kind, test, specimen) -> None:
    """Refuse a test past a model's locking limit on its isochoric path (the incompressible path:
    a compressible card only passes it by a large dilatation). ``kind`` is the test's kind
    (vlab.loading.kinds: ``locking_path(test, specimen)`` gives the [test] key of the load and
    the isochoric F at each load fraction s; ``at`` maps s to the control values)."""
    law = build_material(spec)
    note = law.locking_note
    if note is None:
        return
    from vlab.materials.homogeneous import isochoric_path_limit

    key, path = kind.locking_path(test, specimen)
    s = isochoric_path_limit(law, path)
    if s is not None:
        raise SceneError(f"test.{key}: {note} (material.Jm); the isochoric path of the test "
                         f"reaches it at {key} {_show(kind.at(test.targets, s))}, so {key} {_show(test.targets)} is "
                         f"past the locking limit; lower the {key} or raise material.Jm")


def _show(stretch) -> str:
    return ", ".join(f"{s:.6g}" for s in stretch)
