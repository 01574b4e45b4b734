"""Linear solvers: every installed backend solves, reports inertia, detects singular tangents,
and PARDISO reuses its analysis."""

import numpy as np
import pytest
import scipy.sparse as sp

from vlab.fe import linsolve, pardiso

BACKENDS = [b for b, v in linsolve.available_solvers().items() if v is not None]


def _laplacian_3d(m: int) -> sp.csr_matrix:
    """SPD 7-point Laplacian on an m³ grid (Dirichlet), with stored diagonal."""
    T = sp.diags([-np.ones(m - 1), 2 * np.ones(m), -np.ones(m - 1)], [-1, 0, 1])
    I = sp.identity(m)
    return (sp.kron(sp.kron(T, I), I) + sp.kron(sp.kron(I, T), I) + sp.kron(sp.kron(I, I), T)).tocsr()


@pytest.fixture(autouse=True)
def _restore_choice():
    yield
    linsolve.use_solver("auto")


@pytest.mark.parametrize("backend", BACKENDS)
def test_spd_solve_and_inertia(backend):
    linsolve.use_solver(backend)
    K = _laplacian_3d(6)
    b = np.arange(K.shape[0], dtype=float)
    F = linsolve.factorize(K)
    assert F.backend == backend
    x = F.solve(b)
    assert linsolve.backward_error(K, x, b) < 1e-13
    assert F.negative_pivots == 0


@pytest.mark.parametrize("backend", BACKENDS)
def test_indefinite_inertia_counts_negative_eigenvalues(backend):
    linsolve.use_solver(backend)
    K = _laplacian_3d(5)
    shift = 1.3  # between eigenvalues: exact count from the dense spectrum
    Ki = (K - shift * sp.identity(K.shape[0])).tocsr()
    expected = int(np.sum(np.linalg.eigvalsh(Ki.toarray()) < 0))
    assert 0 < expected < K.shape[0]
    b = np.ones(K.shape[0])
    F = linsolve.factorize(Ki)
    x = F.solve(b)
    assert linsolve.backward_error(Ki, x, b) < 1e-12
    assert F.negative_pivots == expected


@pytest.mark.parametrize("backend", BACKENDS)
def test_singular_matrix_is_reported(backend):
    linsolve.use_solver(backend)
    # pure Neumann Laplacian: constant null space
    T = sp.diags([-np.ones(29), np.r_[1, 2 * np.ones(28), 1], -np.ones(29)], [-1, 0, 1]).tocsr()
    with pytest.raises(linsolve.SingularSystem):
        linsolve.factorize(T).solve(np.linspace(-1, 1, 30) ** 3 + 1.0)


@pytest.mark.skipif(pardiso.library() is None, reason="PARDISO (vlab[fast]) not installed")
def test_pardiso_reuses_analysis_and_keeps_older_factors_valid():
    linsolve.use_solver("pardiso")
    K = _laplacian_3d(6)
    b = np.ones(K.shape[0])
    factors = [linsolve.factorize((s * K).tocsr()) for s in (1.0, 2.0, 3.0, 4.0)]
    patterns = {id(f._pattern) for f in factors}
    assert len(patterns) == 1  # one analysis for one pattern
    for s, f in zip((1.0, 2.0, 3.0, 4.0), factors):  # the first two were evicted from their slots
        assert linsolve.backward_error(s * K, f.solve(b), b) < 1e-13


def test_solver_choice_is_validated():
    with pytest.raises(ValueError, match="linear solver"):
        linsolve.use_solver("cholmod")
    linsolve.use_solver("superlu")
    assert linsolve.solver_in_use() == "superlu"


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_nearly_singular_spd_matrix_is_reported_by_its_condition_number(backend):
    """A Cholesky of an SPD matrix with one eigenvalue ~1e-17 of the others succeeds and is
    backward stable; the solve proves κ∞ > 1e14 and is refused (the cheap norm bound must not
    let it through)."""
    linsolve.use_solver(backend)
    K = _laplacian_3d(4).tolil()
    K[0, 0] = K[0, 0] * 1e-17 + 1e-17  # decouple DOF 0 with a tiny positive stiffness
    K[0, 1:] = 0.0
    K[1:, 0] = 0.0
    K = K.tocsr()
    F = linsolve.factorize(K)
    assert F.norm_bound >= linsolve._norm_inf(K) * (1 - 1e-15)  # an upper bound
    with pytest.raises(linsolve.SingularSystem, match="condition number"):
        F.solve(np.r_[1.0, np.zeros(K.shape[0] - 1)])
    assert abs(F.norm_inf - linsolve._norm_inf(K)) <= 1e-12 * linsolve._norm_inf(K)


@pytest.mark.skipif(pardiso.library() is None, reason="PARDISO (vlab[fast]) not installed")
def test_pardiso_analysis_predicts_a_dense_factor():
    """A full n × n SPD matrix has no fill to order away: its Cholesky factor holds at least
    n(n+1)/2 entries, made in n³/3 flops (leading term), whatever the ordering; PARDISO's
    supernodal storage pads its blocks (96,001 entries and 26 MFLOP at n = 400, measured), so
    the prediction lies between that and twice it."""
    linsolve.use_solver("pardiso")
    n = 400
    A = np.random.default_rng(1).standard_normal((n, n))
    K = sp.csr_matrix(A @ A.T + n * np.eye(n))
    cost = linsolve.factorization_cost(K)
    assert n * (n + 1) // 2 <= cost.factor_nonzeros <= n * n
    assert cost.matrix_nonzeros == n * n
    assert n**3 / 3 / 1e6 - 1 <= cost.mflops <= 2 * n**3 / 3 / 1e6
    assert cost.flops_per_nonzero == pytest.approx(1e6 * cost.mflops / n**2)
    blocks = cost.of_blocks(3)  # every entry a 3 × 3 block: 9 × the entries, 27 × the flops
    assert blocks.flops_per_nonzero == pytest.approx(3 * cost.flops_per_nonzero)
    assert blocks.factor_bytes == 9 * cost.factor_bytes


@pytest.mark.skipif(pardiso.library() is None, reason="PARDISO (vlab[fast]) not installed")
def test_a_late_analysis_voids_older_factors_which_are_then_made_again():
    linsolve.use_solver("pardiso")
    K = _laplacian_3d(6)
    b = np.ones(K.shape[0])
    F = linsolve.factorize(K)
    cost = F._pattern.predicted_cost(F._pattern.upper_values(K))  # analysed anew with the reports
    assert cost.factor_nonzeros > (K.nnz + K.shape[0]) // 2  # a 3D Laplacian fills in
    assert linsolve.backward_error(K, F.solve(b), b) < 1e-13  # refactorized, not a stale factor
    assert linsolve.factorization_cost(K) == cost  # the same prediction from a pattern of its own
    assert linsolve.factorize(K)._pattern is F._pattern  # which left the cached one alone


def test_no_factorization_cost_without_pardiso():
    linsolve.use_solver("superlu")
    assert linsolve.factorization_cost(_laplacian_3d(4)) is None
