"""The closed-form symmetric 3×3 eigensolver (vlab.materials.principal_eig) against LAPACK, and
Ogden's compiled point kernels (vlab.materials.ogden_kernel) against its numpy path: the same ψ,
P and tangent, Taylor tests of order 2 at F = I, equibiaxial F and stretches equal to 1e−8."""

from __future__ import annotations

import numpy as np
import pytest

from helpers_history import random_rotation
from rubber_cards import law
from vlab import jit, settings
from vlab.materials import ogden_kernel
from vlab.materials.principal_eig import eigh3

pytestmark = pytest.mark.skipif(not jit.available(settings.current()), reason="needs numba")

SPECTRA = {"random": None, "double-upper": (1.0, 2.0, 2.0), "double-lower": (1.0, 1.0, 2.0),
           "triple": (1.5, 1.5, 1.5), "near-double 1e-8": (1.0, 1.0 + 1e-8, 2.0),
           "near-triple 1e-8": (1.0 - 1e-8, 1.0, 1.0 + 1e-8), "near-double 1e-13": (0.7, 3.0, 3.0 + 3e-13),
           "indefinite": (-2.0, 0.5, 0.5 + 1e-9), "wide": (1e-6, 1.0, 1e3)}


def matrices(name: str, rng, n: int = 500) -> np.ndarray:
    if SPECTRA[name] is None:
        M = rng.standard_normal((n, 3, 3))
        return M + np.swapaxes(M, 1, 2)
    Q = np.stack([random_rotation(rng) for _ in range(n)])
    return np.einsum("pik,k,pjk->pij", Q, np.array(SPECTRA[name]), Q)


@pytest.mark.parametrize("name", list(SPECTRA))
def test_the_closed_form_eigensolver_matches_lapack_and_reconstructs_the_matrix(name):
    A = matrices(name, np.random.default_rng(len(name)))
    w, V = eigh3(A, compiled=True)
    scale = np.linalg.norm(A, axis=(1, 2))[:, None]
    assert np.max(np.abs(w - np.linalg.eigvalsh(A)) / scale) < 1e-14  # relative to ‖A‖
    assert np.all(np.diff(w, axis=1) >= 0.0)                     # ascending, as eigh
    rebuilt = np.einsum("pik,pk,pjk->pij", V, w, V)
    assert np.max(np.linalg.norm(rebuilt - A, axis=(1, 2)) / scale[:, 0]) < 1e-14
    assert np.abs(np.einsum("pki,pkj->pij", V, V) - np.eye(3)).max() < 1e-14


def test_the_eigensolver_handles_zero_and_scaled_matrices():
    A = np.stack([np.zeros((3, 3)), 1e-200 * np.diag([1.0, 2.0, 3.0]), 1e200 * np.diag([3.0, 1.0, 2.0])] * 30)
    w, V = eigh3(A, compiled=True)
    np.testing.assert_allclose(w[1], 1e-200 * np.array([1.0, 2.0, 3.0]), rtol=1e-14)
    np.testing.assert_allclose(w[2], 1e200 * np.array([1.0, 2.0, 3.0]), rtol=1e-14)
    assert np.all(w[0] == 0.0) and np.all(np.isfinite(V))


def ogden_states(rng, n: int = 80) -> np.ndarray:
    """F (3,3,n): identity, equibiaxial, stretches equal to 1e-8, all equal, random."""
    Fs = []
    for p in range(n):
        kind = p % 5
        diag = ([1.0, 1.0, 1.0], [1.3, 1.3, 0.65], [1.2, 1.2 * (1 + 1e-8), 0.8], [1.1] * 3,
                list(np.exp(0.2 * rng.standard_normal(3))))[kind]
        Fs.append(random_rotation(rng) @ np.diag(diag) @ random_rotation(rng).T if p else np.eye(3))
    return np.stack(Fs, axis=-1)


def forms_tangent(forms) -> np.ndarray:
    """Σ forms c₀ δ_ik δ_JL + δ_ik S_JL + B_ik δ_JL + α X_iJ X_kL + β X_iL X_kJ, written out."""
    I = np.eye(3)
    total = 0.0
    for f in forms:
        A = (np.einsum("ij...,kl...->ijkl...", f.X, f.X) * f.alpha
             + np.einsum("il...,kj...->ijkl...", f.X, f.X) * f.beta)
        A = A + f.c0 * np.einsum("ik,jl->ijkl", I, I)[..., None]
        if f.S is not None:
            A = A + np.einsum("ik,jl...->ijkl...", I, f.S)
        if f.B is not None:
            A = A + np.einsum("ik...,jl->ijkl...", f.B, I)
        total = total + A
    return total


@pytest.mark.parametrize("volumetric", ["quadratic", "log"])
def test_the_compiled_ogden_kernel_gives_the_numpy_energy_stress_and_tangent(volumetric):
    from dataclasses import replace

    m = replace(law("ogden", K=15.0), volumetric=volumetric)
    F = ogden_states(np.random.default_rng(2))
    assert ogden_kernel.kernels(F.shape[-1]) is not None
    psi, P, A, A9 = m.energy(F), m.stress(F), m.tangent(F), forms_tangent(m.tangent_forms(F))
    with settings.using(settings.Settings(kernel="numpy")):
        assert ogden_kernel.kernels(F.shape[-1]) is None
        psi0, P0, A0 = m.energy(F + 0.0), m.stress(F + 0.0), m.tangent(F + 0.0)
    np.testing.assert_allclose(psi, psi0, atol=1e-14)
    np.testing.assert_allclose(P, P0, atol=1e-13)
    np.testing.assert_allclose(A, A0, atol=1e-12 * np.abs(A0).max())
    np.testing.assert_allclose(A9, A0, atol=1e-12 * np.abs(A0).max())


HS = 5e-3 * 0.5 ** np.arange(6)


def test_the_compiled_ogden_stress_and_forms_tangent_pass_the_taylor_test_at_coalescence():
    rng = np.random.default_rng(11)
    m = law("ogden", K=15.0)
    F = ogden_states(rng)
    dF = rng.standard_normal(F.shape)
    psi, P, A = m.energy(F), m.stress(F), forms_tangent(m.tangent_forms(F))
    r_stress = np.array([np.abs(m.energy(F + h * dF) - psi - h * np.einsum("ij...,ij...->...", P, dF))
                         for h in HS])
    r_tangent = np.array([np.abs(m.stress(F + h * dF) - P - h * np.einsum("ijkl...,kl...->ij...", A, dF)
                                 ).max(axis=(0, 1)) for h in HS])
    for r in (r_stress, r_tangent):
        order = np.polyfit(np.log(HS[-3:]), np.log(np.maximum(r[-3:], 1e-300)), 1)[0]
        assert np.all((order > 1.75) & (order < 3.3)), order


def test_the_threaded_ogden_kernels_give_the_serial_results_bit_for_bit():
    m = law("ogden", K=15.0)
    F = np.concatenate([ogden_states(np.random.default_rng(s)) for s in range(60)], axis=-1)  # 4800 points
    assert F.shape[-1] >= ogden_kernel._THREADED_FROM

    def evaluate(threads):
        from vlab.materials import ogden

        ogden._LAST.clear()  # no reuse of the last frame (it is matched by value)
        with settings.using(settings.Settings(assembly_threads=threads)):
            forms = m.tangent_forms(F)
            return m.energy(F), m.stress(F), [(f.X, f.alpha, f.beta) for f in forms]

    (psi1, P1, f1), (psi2, P2, f2) = evaluate(1), evaluate(2)
    module = ogden_kernel.kernels(F.shape[-1])
    assert module.ogden_state_parallel.signatures and module.ogden_forms_parallel.signatures
    assert np.array_equal(psi1, psi2) and np.array_equal(P1, P2)
    assert all(np.array_equal(a, b) for x, y in zip(f1, f2) for a, b in zip(x, y))
