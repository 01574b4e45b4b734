"""The card a fit writes is one `vlab run` accepts, and vlab's own test reproduces the fitted curve."""

import numpy as np

from fit_helpers import spec_of, synthetic
from vlab.identify.fitting import fit_homogeneous
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, response
from vlab.run import run_scene
from vlab.scene import parse_scene


def test_a_neo_hookean_card_runs_in_a_roller_block_and_reproduces_the_fitted_curve():
    model = Constitutive(law_for("neo-hookean"), "fixed", 3.0)
    out = fit_homogeneous(spec_of(model, synthetic(model, [0.45], ["uniaxial", "equibiaxial"]), starts=2))
    card = out.data["card"]["material"]
    scene = parse_scene({"name": "card", "specimen": {"shape": "block", "size": [4.0, 4.0, 4.0]},
                         "mesh": {"size": 4.0, "order": 1, "cell": "hex"}, "material": card,
                         "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.8, "steps": 4}})
    result = run_scene(scene)
    assert result.converged
    stretch = np.array(result.curve.stretch[0])
    fe_stress = result.curve.column("stress")
    closed = np.real(response(model, out.x[None], "uniaxial", stretch))[0]
    assert np.allclose(fe_stress, closed, rtol=1e-6)
