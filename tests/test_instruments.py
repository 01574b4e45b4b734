"""Extensometers located together read exactly what each would read alone, on full and
symmetry-reduced specimens (mirrored marks)."""

import numpy as np
import pytest

from vlab.fe.space import DisplacementSpace
from vlab.measure.instruments import Extensometer, extensometers
from vlab.run import build_specimen
from vlab.scene import parse_scene


@pytest.mark.parametrize("symmetry", ["none", "eighth"])
def test_extensometers_located_in_one_probe_read_as_single_ones(symmetry):
    scene = parse_scene({
        "name": "probe",
        "specimen": {"shape": "dogbone", "standard": "ISO 527-2 1BA"},
        "mesh": {"size": 1.0, "symmetry": symmetry},
        "material": {"model": "neo-hookean", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "stretch": 1.1},
    })
    spec = build_specimen(scene)
    space = DisplacementSpace.build(spec.mesh, 1)
    marks = [spec.extensometers[0], spec.transverse[0], spec.thickness]
    u = 0.05 * np.sin(space.node_coordinates).ravel()
    together = extensometers(space, marks, spec.symmetry)
    for gauge, m in zip(together, marks):
        alone = Extensometer(space, m, spec.symmetry)
        assert gauge.length(u) == pytest.approx(alone.length(u), rel=1e-14)
        assert gauge.length(np.zeros_like(u)) == pytest.approx(m.length, rel=1e-12)
