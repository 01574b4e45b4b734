"""A Gent card's locking stretch is the end of its domain, not a loss of Drucker stability."""

import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

from vlab.identify.drucker import kind_stability, stability_map
from vlab.identify.laws import law_for
from vlab.identify.states import Constitutive

MU, JM = 0.4, 8.6
# incompressible Ī1 − 3 along each path; the chains lock where it reaches Jm
I1_MINUS_3 = {
    "uniaxial": lambda lam: lam ** 2 + 2.0 / lam - 3.0,
    "equibiaxial": lambda lam: 2.0 * lam ** 2 + lam ** -4 - 3.0,
    "planar": lambda lam: lam ** 2 + lam ** -2 - 2.0,
}


def _locking(kind, lo, hi):
    return brentq(lambda lam: I1_MINUS_3[kind](lam) - JM, lo, hi, xtol=1e-14)


@pytest.mark.parametrize("kind", ["uniaxial", "equibiaxial", "planar"])
def test_an_incompressible_gent_card_locks_at_the_closed_form_stretch_and_is_stable_before(kind):
    model = Constitutive(law_for("gent"))
    st = kind_stability(model, np.array([MU, JM]), kind, (1.0, 2.0))
    assert st["tension"]["unstable_from"] is None and st["compression"]["unstable_from"] is None
    assert st["tension"]["locks_at"] == pytest.approx(_locking(kind, 1.0, 10.0), rel=1e-6)
    assert st["compression"]["locks_at"] == pytest.approx(_locking(kind, 0.1, 1.0), rel=1e-6)
    assert st["stable_over_fitted_range"]


def test_data_past_the_locking_stretch_is_outside_the_stable_range():
    model = Constitutive(law_for("gent"))
    lock = _locking("uniaxial", 1.0, 10.0)
    st = kind_stability(model, np.array([MU, JM]), "uniaxial", (1.0, 1.01 * lock))
    assert not st["stable_over_fitted_range"]


def test_a_compressible_gent_scan_raises_no_numpy_warning_and_reports_locking_not_instability():
    model = Constitutive(law_for("gent"), bulk="fit")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = {k: kind_stability(model, np.array([MU, JM, 3.0]), k, None) for k in I1_MINUS_3}
    for kind, st in out.items():
        assert st["tension"]["unstable_from"] is None, kind
        lock = st["tension"]["locks_at"]  # near the incompressible value (K/μ = 7.5: a few per cent)
        assert lock == pytest.approx(_locking(kind, 1.0, 10.0), rel=0.1), kind


def test_the_stability_map_has_no_eigenvalue_beyond_locking_and_a_positive_one_inside():
    model = Constitutive(law_for("gent"))
    sm = stability_map(model, np.array([MU, JM]), n=41)
    lam, m = sm["stretch"], sm["min_eigenvalue"]
    L1, L2 = np.meshgrid(lam, lam, indexing="ij")
    i1 = L1 ** 2 + L2 ** 2 + (L1 * L2) ** -2 - 3.0
    assert np.all(np.isnan(m[i1 >= JM * (1 + 1e-9)]))
    assert np.all(m[i1 < JM * (1 - 1e-9)] > 0)
