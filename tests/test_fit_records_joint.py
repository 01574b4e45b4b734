"""Viscoelasticity and Mullins softening fitted together from rate-dependent cycles.

The records are made with vlab's history materials (vlab.materials.viscoelastic.PronyViscoelastic
and vlab.materials.mullins.OgdenRoxburgh, the laws `vlab run` integrates), not with the fit's own
forward model: at each row F = diag(λ, λ^(−1/2), λ^(−1/2)) (J = 1), the joint model's Cauchy
stress is η σ0 + F Q Fᵀ (the softened ground stress plus the Maxwell branches of the viscoelastic
law's response minus its ground stress), and the uniaxial nominal stress is
P1 = (σ11 − σ22)/λ. The noise-free fit must return every constant to 1e-6 relative.
"""

from __future__ import annotations

import numpy as np
import pytest

from vlab.identify.datasets import Dataset
from vlab.identify.fitfile import FitSpec
from vlab.identify.fitting import fit_any
from vlab.identify.laws import law_for
from vlab.identify.records.prony import PronySpec
from vlab.identify.records.softening import MullinsSpec
from vlab.identify.states import Constitutive
from vlab.materials.card import build_material, parse_material
from vlab.materials.mullins import OgdenRoxburgh
from vlab.materials.viscoelastic import PronyViscoelastic

NH = Constitutive(law_for("neo-hookean"))
MU, BETA, TAU, R, M, MB = 0.6, (0.5, 0.3), (1.0, 10.0), 2.0, 0.3, 0.1


def _history(rate: float, amplitudes=(1.5, 2.0, 2.5), hold: float = 10.0, h: float = 0.05):
    """(t, λ): triangles 1 → a → 1 at |dλ/dt| = rate in stretch steps h, a hold at each peak."""
    lam, t, now = [], [], 0.0
    for a in amplitudes:
        up = np.arange(1.0 + h, a + h / 2, h)
        seg = list(up)
        seg_t = list(now + (up - 1.0) / rate)
        now = seg_t[-1]
        seg += [a] * 4  # the hold at the peak
        seg_t += list(now + np.geomspace(hold / 8, hold, 4))
        now = seg_t[-1]
        down = np.arange(a - h, 1.0 - h / 2, -h)
        seg += list(down)
        seg_t += list(now + (a - down) / rate)
        now = seg_t[-1]
        lam += seg
        t += seg_t
    return np.asarray(t), np.asarray(lam)


def _record(t, lam):
    ground = build_material(parse_material({"model": "neo-hookean", "mu": MU, "K": 1000 * MU}))
    visco = PronyViscoelastic(ground, tau=TAU, beta=BETA)
    soft = OgdenRoxburgh(ground, r=R, m=M, beta=MB)
    sv, sm = visco.initial_state((1,)), soft.initial_state((1,))
    out, t_prev = [], 0.0
    for tk, lk in zip(t, lam):
        F = np.diag([lk, lk ** -0.5, lk ** -0.5])[:, :, None]
        dt = tk - t_prev
        P0 = ground.stress(F)
        sigma = np.einsum("ijk,ljk->il", soft.respond(F, sm, dt, with_tangent=False).stress
                          + visco.respond(F, sv, dt, with_tangent=False).stress - P0, F)
        out.append((sigma[0, 0] - sigma[1, 1]) / lk)
        sv, sm, t_prev = visco.update(F, sv, dt), soft.update(F, sm, dt), tk
    return np.asarray(out)


def _set(name, rate):
    t, lam = _history(rate)
    y = _record(t, lam)
    extra = {"test": "uniaxial", "stretch": lam, "time": t, "mask": np.ones(len(lam), bool), "branch": "all"}
    return Dataset(name, f"{name}.csv", "cyclic", "fit", 1.0, "nominal", lam, None, y, extra=extra)


def test_the_joint_fit_returns_prony_mullins_and_ground_constants_to_1e_6():
    sets = (_set("slow", 0.05), _set("fast", 0.5))
    effects = {"viscoelastic": PronySpec(2), "mullins": MullinsSpec()}
    out = fit_any(FitSpec("joint", NH, sets, starts=4, effects=effects))
    p = out.data["parameters"]
    want = {"mu": MU, "beta": BETA, "tau": TAU, "r": R, "m": M, "mullins_beta": MB}
    for k, v in want.items():
        got = np.atleast_1d(p[k])
        assert np.allclose(got, v, rtol=1e-6, atol=0), (k, got, v)
    card = out.data["card"]
    assert set(card["effects"]) == {"viscoelastic", "mullins"}
    assert out.data["converged"]


def test_the_fits_forward_model_is_the_history_materials():
    from vlab.identify.records.cyclic import stress_along

    t, lam = _history(0.5)
    x = np.r_[MU, BETA, TAU, R, M, MB][None, :]
    effects = {"viscoelastic": PronySpec(2), "mullins": MullinsSpec()}
    pred = np.real(stress_along(NH, effects, x, "uniaxial", lam, t)[0])
    ref = _record(t, lam)
    assert np.max(np.abs(pred - ref)) <= 1e-10 * np.max(np.abs(ref))


@pytest.mark.parametrize("drop", ("viscoelastic", "mullins"))
def test_the_joint_model_without_one_part_is_the_other_fit(drop):
    from vlab.identify.records.cyclic import stress_along

    t, lam = _history(0.5)
    full = {"viscoelastic": PronySpec(2), "mullins": MullinsSpec()}
    one = {k: (None if k == drop else v) for k, v in full.items()}
    x = {"viscoelastic": np.r_[MU, R, M, MB], "mullins": np.r_[MU, BETA, TAU]}[drop][None, :]
    inert = {"viscoelastic": np.r_[MU, 0.0, 0.0, 1.0, 1.0, R, M, MB],  # β = 0: no branch stress
             "mullins": np.r_[MU, BETA, TAU, 2.0, 1e300, 0.0]}[drop][None, :]  # m → ∞: η = 1
    a = np.real(stress_along(NH, one, x, "uniaxial", lam, t)[0])
    b = np.real(stress_along(NH, full, inert, "uniaxial", lam, t)[0])
    assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(a))
