"""Laws and bodies declare their optional capabilities (vlab/materials/capabilities.py,
vlab/fe/body.py) instead of being probed for them with hasattr/getattr."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import rubber_cards
from vlab.fe.body import BodyDefaults
from vlab.materials import MODELS, make_material
from vlab.materials.capabilities import LawCapabilities
from vlab.materials.plane import PlaneStrain, PlaneStress

PACKAGE = Path(__file__).resolve().parents[1] / "vlab"
CAPABILITIES = ("tangent_terms", "tangent_forms", "history_fields", "is_linear", "locking_note")
BODY_MEMBERS = ("advance", "constraint", "volume_change", "set_load", "load_rate")


def _laws():
    for name, entry in MODELS.items():
        if not entry.continuum:
            continue
        law = rubber_cards.law(name) if name in rubber_cards.CARDS else make_material(name, 5.77, 3.85)
        yield name, law
        yield f"{name} (plane stress)", PlaneStress(law)
        yield f"{name} (plane strain)", PlaneStrain(law)


@pytest.mark.parametrize("name,law", list(_laws()), ids=lambda x: x if isinstance(x, str) else "")
def test_every_law_of_the_registry_declares_each_capability_as_a_member_or_none(name, law):
    assert isinstance(law, LawCapabilities)
    for capability in CAPABILITIES[:3]:
        value = getattr(law, capability)
        assert value is None or callable(value), (name, capability)
    assert isinstance(law.is_linear, bool) and (law.locking_note is None or isinstance(law.locking_note, str))
    assert law.plane == ("stress" if "stress" in name else "strain" if "strain" in name else "")
    assert not law.plane or isinstance(law.base, LawCapabilities)


def test_the_laws_with_memory_declare_their_history_fields():
    from vlab.materials.history import HistoryMaterial
    from vlab.materials.mullins import OgdenRoxburgh
    from vlab.materials.plasticity import J2Plasticity
    from vlab.materials.viscoelastic import PronyViscoelastic

    for cls in (OgdenRoxburgh, J2Plasticity, PronyViscoelastic):
        assert issubclass(cls, HistoryMaterial) and cls.history_fields is not None
    assert make_material("neo-hookean", 5.77, 3.85).history_fields is None


def test_every_body_class_declares_the_optional_members_of_the_body_interface():
    import vlab.fe.external_load, vlab.fe.history_body, vlab.fe.liquid, vlab.fe.mixed, vlab.fe.problem  # noqa: E401,F401
    import vlab.fe.spring_network  # noqa: F401

    def subclasses(cls) -> list[type]:  # the wrappers of vlab.fe.body.LoadWrapper are a level down
        return [c for sub in cls.__subclasses__() for c in (sub, *subclasses(sub))]

    bodies = subclasses(BodyDefaults)
    assert {b.__name__ for b in bodies} >= {"HyperelasticBody", "MixedHyperelasticBody", "SpringNetwork",
                                           "HistoryBody", "LoadedBody", "LiquidBody"}
    assert BodyDefaults.advance is None and vlab.fe.mixed.MixedHyperelasticBody.advance is not None


def test_no_module_probes_a_declared_capability_by_name():
    """hasattr(x, "tangent_terms") or getattr(x, "advance", None) would bypass the declarations (and
    hasattr is now always true: the defaults are declared), in the package and in its tests."""
    probes = []
    for path in sorted(PACKAGE.rglob("*.py")) + sorted(PACKAGE.parent.joinpath("tests").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                    and node.func.id in ("hasattr", "getattr") and len(node.args) >= 2
                    and isinstance(node.args[1], ast.Constant) and node.args[1].value in CAPABILITIES + BODY_MEMBERS):
                probes.append(f"{path.relative_to(PACKAGE.parent)}:{node.lineno} {node.args[1].value}")
    assert probes == []
