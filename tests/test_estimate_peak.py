"""The accuracy estimate reads the final stress at the largest deformation of every test kind:
the largest |λ − 1| of the grip stretch, and for simple shear the largest |γ| (it read the first
level, where |γ − 1| is largest, before issue #30)."""

from types import SimpleNamespace

import pytest

from vlab.loading.kinds import KINDS
from vlab.measure.recorder import Curve
from vlab.study.estimate import _values, peak_level


def _curve(kind, control, stress):
    return Curve(t=list(range(len(control))), stretch={0: list(control)}, force={0: list(stress)},
                 strain={0: [0.0] * len(control)}, area0={0: 1.0}, kind=kind)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_the_final_stress_is_read_at_the_largest_deformation_of_every_kind(kind):
    if KINDS[kind].rest == 0.0:
        control, peak = [0.1, 0.4, 0.8, 1.2], 3     # γ or ψ: |γ − 1| is largest at the first level
    else:
        control, peak = [1.05, 1.3, 1.8, 1.2], 2    # a load-unload record ends below its peak
    stress = [10.0 * (i + 1) for i in range(len(control))]
    curve = _curve(kind, control, stress)
    assert peak_level(curve) == peak
    values = _values(SimpleNamespace(curve=curve, constants=SimpleNamespace(E=1.0, nu=0.3)))
    assert values["final_stress"] == stress[peak]


def test_a_cyclic_record_peaks_at_its_largest_stretch_not_its_last_load_parameter():
    curve = _curve("uniaxial", [1.2, 1.5, 1.1, 1.8, 1.0], [0] * 5)
    assert curve.t == [0, 1, 2, 3, 4] and peak_level(curve) == 3


def test_a_compression_test_peaks_at_its_smallest_stretch():
    assert peak_level(_curve("uniaxial", [0.95, 0.7, 0.5, 0.8], [0, 0, 0, 0])) == 2
