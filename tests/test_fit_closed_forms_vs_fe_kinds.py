"""The closed forms the fits use for planar tension and simple shear are the FE test kinds' own
homogeneous states: vlab's roller block (planar) and kinematic block (simple shear) read the same
nominal stresses at every recorded level, to 1e-6 (measured: 6e-11 and 2e-13)."""

import warnings

import numpy as np
import pytest

from vlab.identify.fe_stress import flat_constants
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, response
from vlab.run import run_scene
from vlab.scene import parse_scene

MATERIALS = [
    {"model": "mooney-rivlin", "C10": 0.2, "C01": 0.05, "K": 4.0},
    {"model": "ogden", "mu": [0.3, 0.02], "alpha": [1.8, 5.0], "K": 10.0},
    {"model": "gent", "mu": 0.4, "Jm": 12.0, "K": 3.0, "volumetric": "log"},
]
TESTS = [{"kind": "planar", "grips": "roller", "stretch": 1.6, "steps": 4},
         {"kind": "simple-shear", "grips": "kinematic", "shear": 0.8, "steps": 4}]


def _closed_form(material):
    v = flat_constants(material)
    law = law_for(material.model, sum(1 for n in v if n.startswith("alpha[")) or 1)
    model = Constitutive(law, "fixed", v["K"], material.volumetric or "quadratic")
    x = np.linalg.solve(law.transform, np.array([v[n] for n in law.names]))  # card = T x
    return model, x[None, :]


@pytest.mark.parametrize("test", TESTS, ids=lambda t: t["kind"])
@pytest.mark.parametrize("material", MATERIALS, ids=lambda m: m["model"])
def test_the_fits_closed_form_reads_what_vlabs_homogeneous_block_reads(material, test):
    raw = {"name": "x", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
           "mesh": {"size": 2.0, "order": 1, "cell": "hex"}, "material": material, "test": test}
    scene = parse_scene(raw, "x", ".")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_scene(scene)
    assert result.converged
    curve = result.curve
    control = np.array(curve.stretch[0])  # grip stretch, or the plate-travel shear γ
    fe = np.array(curve.force[0]) / curve.area0[0]
    model, x = _closed_form(scene.material)
    predicted = response(model, x, test["kind"], control)[0]
    assert len(control) >= 4 and np.max(np.abs(control - (1.0 if test["kind"] == "planar" else 0.0))) > 0.5
    assert np.max(np.abs(predicted - fe)) <= 1e-6 * np.max(np.abs(fe))
