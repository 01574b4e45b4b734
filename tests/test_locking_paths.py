"""The locking-limit check (vlab.materials.card.check_path) reads each kind's own control: a
membrane's volume ratio is not a stretch, a cylinder's twist locks at its surface shear.

References from their formulas: Gent locks at Ī₁ − 3 = Jm. The surface of a twisted cylinder is
in simple shear γ = ψ a, Ī₁ − 3 = γ², so ψ = √Jm / a. The least-area cap over the rim holding the
bulge's volume has the area ratio A = 1 + η² (η³ + 3η = 6 (v − 1)); the equibiaxial state of area
stretch A has Ī₁ = 2A + A⁻².
"""

from __future__ import annotations

import math

import pytest
from scipy.optimize import brentq

from vlab.fields import SceneError
from vlab.loading.bulge import cap_area_ratio
from vlab.scene import parse_scene

JM = 12.0
GENT = {"model": "gent", "mu": 0.4, "Jm": JM, "K": 400.0}


def membrane(volume_ratio: float) -> dict:
    return {"name": "bulge", "specimen": {"shape": "membrane", "radius": 10.0, "thickness": 0.2},
            "mesh": {"size": 2.5, "cell": "hex", "formulation": "mixed"}, "material": GENT,
            "test": {"kind": "inflation", "grips": "clamped", "volume_ratio": volume_ratio, "steps": 4}}


def cylinder(twist: float, radius: float = 2.0) -> dict:
    return {"name": "torsion", "specimen": {"shape": "cylinder", "radius": radius, "length": 4.0},
            "mesh": {"size": 1.0, "cell": "hex", "formulation": "mixed"}, "material": GENT,
            "test": {"kind": "torsion", "grips": "clamped", "twist": twist, "steps": 4}}


def test_the_cap_area_ratio_of_a_hemisphere_is_two():
    assert cap_area_ratio(1.0 + 2.0 / 3.0) == pytest.approx(2.0, rel=1e-12)  # 2πa² over πa²
    eta = math.sqrt(cap_area_ratio(2.5) - 1.0)
    assert eta**3 + 3.0 * eta == pytest.approx(6.0 * 1.5, rel=1e-12)


def test_a_membrane_s_volume_ratio_is_not_read_as_a_stretch():
    # read as an equibiaxial stretch λ = v, v = 3 would give Ī₁ − 3 = 2·9 + 3⁻⁴ − 3 > Jm: refused;
    # its least-area cap (A ≈ 4.4) is far from the limit, so the check must let it run
    parse_scene(membrane(3.0))


def test_a_membrane_is_refused_where_its_least_area_cap_locks():
    area = brentq(lambda a: 2.0 * a + a**-2 - 3.0 - JM, 1.0, 50.0)  # the equibiaxial lock
    eta = math.sqrt(area - 1.0)
    v_lock = 1.0 + eta * (3.0 + eta**2) / 6.0
    parse_scene(membrane(0.99 * v_lock))
    with pytest.raises(SceneError) as err:
        parse_scene(membrane(1.01 * v_lock))
    text = str(err.value)
    assert "test.volume_ratio:" in text and f"at volume_ratio {v_lock:.6g}" in text


def test_a_twisted_cylinder_is_refused_where_its_surface_locks():
    radius = 2.0
    psi_lock = math.sqrt(JM) / radius
    parse_scene(cylinder(0.99 * psi_lock, radius))
    with pytest.raises(SceneError) as err:
        parse_scene(cylinder(1.01 * psi_lock, radius))
    assert "test.twist:" in str(err.value) and f"at twist {psi_lock:.6g}" in str(err.value)
