"""The identification closed forms against the FE model library's materials (issue #18's cards):
the same card gives the same homogeneous stresses, and every card a fit writes is one the
library's parser accepts."""

import numpy as np
import pytest

import vlab.materials.card as card_module

from fit_helpers import spec_of, synthetic
from vlab.identify.fitting import fit_homogeneous
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive, response
from vlab.materials.homogeneous import biaxial, uniaxial

CARDS = [("mooney-rivlin", 1, [0.25, 0.05]), ("yeoh", 1, [0.2, -0.008, 0.0006]), ("gent", 1, [0.4, 30.0]),
         ("arruda-boyce", 1, [0.4, 4.0]), ("ogden", 3, [0.05, 0.3, 0.0005, -1.5, 1.8, 6.0])]


def _library(law, values, K, volumetric):
    table = law.card(values) | {"K": K, "volumetric": volumetric}
    return card_module.build_material(card_module.parse_material(table))


@pytest.mark.parametrize("name,terms,values", CARDS, ids=[c[0] for c in CARDS])
@pytest.mark.parametrize("volumetric", ["quadratic", "log", "simo-taylor"])
def test_closed_forms_match_the_fe_librarys_homogeneous_states(name, terms, values, volumetric):
    law = law_for(name, terms)
    model = Constitutive(law, "fixed", 20.0, volumetric)
    material = _library(law, values, 20.0, volumetric)
    x = np.linalg.solve(law.transform, values)[None]
    for lam in (0.7, 1.3, 2.0):
        P = np.real(response(model, x, "uniaxial", [lam]))[0, 0]
        assert P == pytest.approx(uniaxial(material, lam).nominal_stress, rel=1e-8, abs=1e-12)
        Pb = np.real(response(model, x, "biaxial", [lam], [1.2]))[0]
        ref = biaxial(material, lam, 1.2).P
        assert Pb == pytest.approx([ref[0, 0], ref[1, 1]], rel=1e-8, abs=1e-12)


@pytest.mark.parametrize("name,terms,values", CARDS, ids=[c[0] for c in CARDS])
def test_every_card_a_fit_writes_is_accepted_by_the_librarys_parser(name, terms, values):
    model = Constitutive(law_for(name, terms))
    out = fit_homogeneous(spec_of(model, synthetic(model, values, ("uniaxial", "equibiaxial", "planar")), starts=4))
    spec = card_module.parse_material(out.data["card"]["material"])
    assert spec.model == name
