"""Assembly kernels: the fast reference-cell stiffness equals the textbook contraction and the
derivative of the internal force, on distorted meshes of every element type."""

import numpy as np
import pytest
import skfem

from vlab import jit
from vlab.settings import Settings
from vlab.fe import assembly, compiled
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.geometry.block import block_mesh
from vlab.materials import make_material

CASES = [("hex", 1), ("hex", 2), ("tet", 1), ("tet", 2)]


def _space(cell: str, order: int) -> DisplacementSpace:
    mesh = block_mesh((2.0, 1.5, 1.0), 0.5, cell)
    distorted = mesh.p + 0.04 * np.sin(3.0 * mesh.p[[1, 2, 0]])  # curved, non-affine cells
    return DisplacementSpace.build(type(mesh)(distorted, mesh.t), order)


@pytest.mark.parametrize("cell,order", CASES)
def test_reference_map_reproduces_gradients(cell, order):
    space = _space(cell, order)
    assert space.reference_dN is not None
    rebuilt = np.einsum("qam,mJeq->eqaJ", space.reference_dN, space.inverse_jacobian)
    np.testing.assert_allclose(rebuilt, space.dN, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("cell,order", CASES)
def test_fast_stiffness_equals_textbook_contraction(cell, order):
    space = _space(cell, order)
    material = make_material("neo-hookean", 5.0, 2.0)
    u = 0.02 * np.random.default_rng(1).standard_normal(space.n_dofs)
    A = material.tangent(space.deformation_gradient(u))
    textbook = np.einsum("eqaJ,iJkLeq,eqbL,eq->ikeab", space.dN, A, space.dN, space.dx)
    for kernel in (assembly.element_stiffness, assembly._element_stiffness_generic):
        Ke = kernel(space, A)
        assert Ke.shape == textbook.shape
        np.testing.assert_allclose(Ke, textbook, rtol=0, atol=1e-12 * np.abs(textbook).max())


@pytest.mark.parametrize("model", ["neo-hookean", "stvk", "linear"])
@pytest.mark.parametrize("cell,order", CASES)
def test_tangent_terms_pulled_back_equal_the_full_tangent_kernel(cell, order, model):
    space = _space(cell, order)
    material = make_material(model, 5.0, 2.0)
    F = space.deformation_gradient(0.02 * np.random.default_rng(3).standard_normal(space.n_dofs))
    terms = material.tangent_terms(F)
    np.testing.assert_allclose(terms.full(), material.tangent(F), rtol=0, atol=1e-13)
    textbook = np.einsum("eqaJ,iJkLeq,eqbL,eq->ikeab", space.dN, material.tangent(F), space.dN,
                         space.dx)
    Ke = assembly.element_stiffness(space, terms)
    np.testing.assert_allclose(Ke, textbook, rtol=0, atol=1e-12 * np.abs(textbook).max())
    pattern = assembly.SparsityPattern.build(space.element_nodes)  # any memory layout scatters alike
    K_fast, K_copy = pattern.matrix(Ke), pattern.matrix(np.ascontiguousarray(Ke))
    assert abs(K_fast - K_copy).max() <= 1e-14 * abs(K_copy).max()


@pytest.mark.parametrize("cell,order", [("hex", 1), ("tet", 2)])
def test_stiffness_is_the_derivative_of_the_internal_force(cell, order):
    space = _space(cell, order)
    body = HyperelasticBody(space, make_material("neo-hookean", 5.0, 2.0))
    rng = np.random.default_rng(2)
    u = 0.02 * rng.standard_normal(space.n_dofs)
    du = rng.standard_normal(space.n_dofs)
    ev = body.evaluate(u)
    K = body.stiffness(ev)
    h = 1e-6
    fd = (body.evaluate(u + h * du).f_int - body.evaluate(u - h * du).f_int) / (2 * h)
    np.testing.assert_allclose(K @ du, fd, rtol=0, atol=1e-6 * np.abs(fd).max())
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()


def test_no_reference_map_falls_back_to_generic_kernel():
    space = _space("hex", 1)
    plain = DisplacementSpace(space.basis, space.element_nodes, space.dN, space.dx)
    A = make_material("stvk", 5.0, 2.0).tangent(plain.deformation_gradient(np.zeros(plain.n_dofs)))
    np.testing.assert_allclose(assembly.element_stiffness(plain, A),
                               assembly.element_stiffness(space, A), atol=1e-12)


def test_sparsity_pattern_covers_every_element_coupling():
    mesh = skfem.MeshTet.init_tensor(*[np.linspace(0, 1, 3)] * 3)
    space = DisplacementSpace.build(mesh, 1)
    pattern = assembly.SparsityPattern.build(space.element_nodes)
    n_el, n_loc = space.element_nodes.shape
    K = pattern.matrix(np.ones((3, 3, n_el, n_loc, n_loc)))
    assert K.shape == (space.n_dofs, space.n_dofs)
    assert abs(K - K.T).max() == 0
    # each diagonal entry counts the elements sharing that node
    shared = np.bincount(space.element_nodes.ravel(), minlength=space.n_nodes)
    np.testing.assert_array_equal(K.diagonal(), np.repeat(shared, 3))


KERNELS = ["numpy", pytest.param("compiled", marks=pytest.mark.skipif(
    not compiled.available(Settings()), reason="numba not installed"))]


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("model", ["neo-hookean", "stvk", "linear"])
@pytest.mark.parametrize("cell,order", CASES)
def test_symmetric_assembly_of_six_blocks_equals_the_full_scatter(cell, order, model, kernel):
    """The body's stiffness is the textbook K with either kernel: numpy (blocks i ≤ k
    scattered, i > k mirrored) or compiled (isotropic form, node blocks added to the CSR)."""
    space = _space(cell, order)
    material = make_material(model, 5.0, 2.0)
    body = HyperelasticBody(space, material, kernel=kernel)
    assert body.tangent_kernel.startswith(kernel)
    ev = body.evaluate(0.02 * np.random.default_rng(4).standard_normal(space.n_dofs))
    textbook = np.einsum("eqaJ,iJkLeq,eqbL,eq->ikeab", space.dN, material.tangent(ev.F), space.dN,
                         space.dx)
    K_full = body.pattern.matrix(np.ascontiguousarray(textbook))
    K = body.stiffness(ev)
    assert K.has_sorted_indices and np.array_equal(K.indptr, K_full.indptr)
    assert abs(K - K_full).max() <= 1e-12 * abs(K_full).max()


@pytest.mark.parametrize("dim", [3, 2])
def test_sparsity_pattern_from_node_pairs_equals_the_dof_pattern(dim):
    """The CSR built from node pairs is the sorted, duplicate-free DOF pattern of the elements,
    and ``slot`` sends every element entry (i, k, e, a, b) to the CSR index of its DOF pair."""
    rng = np.random.default_rng(5)
    nodes = np.array([rng.choice(40, size=6, replace=False) for _ in range(30)])
    nodes[0, 0] = 39  # the largest node is used
    pattern = assembly.SparsityPattern.build(nodes, dim)
    comp = np.arange(dim)
    rows = dim * nodes[None, None, :, :, None] + comp[:, None, None, None, None]
    cols = dim * nodes[None, None, :, None, :] + comp[None, :, None, None, None]
    rows, cols = (a.ravel() for a in np.broadcast_arrays(rows, cols))
    expected = sorted(set(zip(rows.tolist(), cols.tolist())))
    csr_rows = np.repeat(np.arange(pattern.n), np.diff(pattern.indptr))
    assert list(zip(csr_rows.tolist(), pattern.indices.tolist())) == expected
    np.testing.assert_array_equal(csr_rows[pattern.slot], rows)
    np.testing.assert_array_equal(pattern.indices[pattern.slot], cols)


def _isotropic_full(form, batch) -> np.ndarray:
    """c₀ δ_ik δ_JL + δ_ik S_JL + B_ik δ_JL + α X_iJ X_kL + β X_iL X_kJ, written out."""
    I = np.eye(3)
    ones = np.ones(batch)
    A = np.einsum("ik,JL,...->iJkL...", I, I, form.c0 * ones)
    if form.S is not None:
        A += np.einsum("ik,JL...->iJkL...", I, form.S)
    if form.B is not None:
        A += np.einsum("ik...,JL->iJkL...", form.B, I)
    X = form.X
    A += np.einsum("iJ...,kL...,...->iJkL...", X, X, form.alpha * ones)
    A += np.einsum("iL...,kJ...,...->iJkL...", X, X, form.beta * ones)
    return A


@pytest.mark.parametrize("model", ["neo-hookean", "stvk", "linear"])
def test_isotropic_form_of_the_three_models_is_their_tangent(model):
    material = make_material(model, 5.0, 2.0)
    rng = np.random.default_rng(6)
    F = np.eye(3)[:, :, None, None] + 0.2 * rng.standard_normal((3, 3, 4, 5))
    form = material.tangent_terms(F).isotropic()
    assert form is not None
    np.testing.assert_allclose(_isotropic_full(form, (4, 5)), material.tangent(F), rtol=0,
                               atol=1e-12 * np.abs(material.tangent(F)).max())


def test_terms_of_another_form_have_no_isotropic_form():
    from vlab.materials.structure import TangentTerms
    rng = np.random.default_rng(7)
    P, Q = rng.standard_normal((2, 3, 3, 4))
    assert TangentTerms((4,), dyad=[(P, P)], cross=[(Q, Q)]).isotropic() is None  # two fields
    assert TangentTerms((4,), dyad=[(P, P)]).isotropic() is None                   # no cross
    assert TangentTerms((4,), kron=[(P, Q)], dyad=[(P, P)], cross=[(P, P)]).isotropic() is None
    form = TangentTerms((4,), kron=[(2.0, 1.0), (1.0, Q), (P, 3.0)], dyad=[((1.5, P), P)],
                        cross=[(P, P)]).isotropic()
    assert form.c0 == 2.0 and form.S is Q and np.array_equal(form.B, 3.0 * P)
    assert form.alpha == 1.5 and form.beta == 1.0 and form.X is P


@pytest.mark.skipif(not compiled.available(Settings()), reason="numba not installed")
def test_compiled_kernel_without_a_writable_cache_compiles_in_memory(monkeypatch):
    """No writable directory for the generated source: the kernel is compiled from memory (no
    on-disk cache) and gives the same K."""
    space = _space("tet", 1)
    material = make_material("neo-hookean", 5.0, 2.0)
    ev = HyperelasticBody(space, material, kernel="numpy").evaluate(
        0.02 * np.random.default_rng(8).standard_normal(space.n_dofs))
    reference = HyperelasticBody(space, material, kernel="numpy").stiffness(ev)
    monkeypatch.setattr(compiled, "_KERNELS", {})
    monkeypatch.setattr(jit, "source_dir", lambda: None)
    K = HyperelasticBody(space, material, kernel="compiled").stiffness(ev)
    assert abs(K - reference).max() <= 1e-12 * abs(reference).max()


needs_numba = pytest.mark.skipif(not compiled.available(Settings()), reason="numba not installed")


def _state(space, model="neo-hookean"):
    material = make_material(model, 5.0, 2.0)
    ev = HyperelasticBody(space, material, kernel="numpy").evaluate(
        0.02 * np.random.default_rng(9).standard_normal(space.n_dofs))
    return material, ev, HyperelasticBody(space, material, kernel="numpy").stiffness(ev)


@needs_numba
@pytest.mark.parametrize("cell,order", CASES)
def test_threads_assembling_slabs_side_by_side_give_the_serial_K(cell, order):
    """Slabs of one parity share no node, so threads add into disjoint entries: the K of 2
    threads (4 slabs of the swept mesh: its 4 hexahedron layers along x) equals the numpy
    kernel's, and 3 threads fall back to 2 (6 slabs would not separate)."""
    space = _space(cell, order)
    material, ev, reference = _state(space)
    body = HyperelasticBody(space, material, kernel="compiled")
    for threads in (2, 3):
        bounds = compiled.slabs(space.element_nodes, threads, min_elements=2)
        assert len(bounds) == 5
        body._compiled.__dict__["bounds"] = bounds
        K = body.stiffness(ev)
        assert abs(K - reference).max() <= 1e-12 * abs(reference).max()


@needs_numba
@pytest.mark.parametrize("cell,order", CASES)
def test_compiled_deformation_gradient_and_internal_force_equal_numpy(cell, order):
    """F and f_int of the compiled kernels equal the space's numpy contractions (and so the
    evaluation of a body with either kernel)."""
    space = _space(cell, order)
    material = make_material("neo-hookean", 5.0, 2.0)
    u = 0.02 * np.random.default_rng(11).standard_normal(space.n_dofs)
    fast, slow = (HyperelasticBody(space, material, kernel=k) for k in ("compiled", "numpy"))
    F = space.deformation_gradient(u)
    np.testing.assert_allclose(fast._compiled.deformation_gradient(u), F, rtol=0, atol=1e-14)
    P = material.stress(F)
    element = assembly.element_forces(space, P)
    f = assembly.scatter_vector(space, element)
    scale = 1e-13 * np.abs(element).max()  # nodal sums cancel: round-off is relative to the terms
    np.testing.assert_allclose(fast._compiled.internal_force(P), f, rtol=0, atol=scale)
    a, b = fast.evaluate(u), slow.evaluate(u)
    assert a.W == pytest.approx(b.W, rel=1e-13) and a.min_J == pytest.approx(b.min_J, rel=1e-13)
    np.testing.assert_allclose(a.f_int, b.f_int, rtol=0, atol=scale)


@needs_numba
def test_compiled_inverse_transpose_equals_the_cofactor_formula():
    """tensor.inv_transpose on a mesh-sized batch (compiled) against cof F / det F (numpy), on
    a non-contiguous F, with a singular point giving inf/nan as the numpy formula does."""
    from vlab import tensor
    rng = np.random.default_rng(12)
    F = (np.eye(3)[:, :, None, None] + 0.3 * rng.standard_normal((3, 3, 8, 64)))[:, :, :, ::2]
    F[:, :, 1, 3] = 0.0
    assert F[0, 0].size >= tensor._COMPILED_FROM and not F.flags.c_contiguous
    G, J = tensor.inv_transpose(F)
    cof = tensor.cofactor(F)
    J0 = tensor.det(F, cof)
    with np.errstate(divide="ignore", invalid="ignore"):
        G0 = cof / J0
    np.testing.assert_array_equal(J, J0)
    assert G.shape == F.shape and np.isnan(G[0, 0, 1, 3]) and np.all(np.isnan(G0[:, :, 1, 3]))
    ok = np.isfinite(G0)
    np.testing.assert_allclose(G[ok], G0[ok], rtol=4e-16 * 8, atol=0)


def test_slabs_split_only_where_no_node_is_in_two_slabs_of_one_parity():
    nodes = block_mesh((4.0, 1.0, 1.0), 0.25, "hex").t.T       # swept: x slowest, 16 layers
    bounds = compiled.slabs(nodes, 2, min_elements=16)
    assert len(bounds) == 5 and bounds[0] == 0 and bounds[-1] == len(nodes)
    slab = np.repeat(np.arange(4), np.diff(bounds))
    for s in range(4):
        for other in range(s + 2, 4, 2):
            assert not set(nodes[slab == s].ravel()) & set(nodes[slab == other].ravel())
    shuffled = nodes[np.random.default_rng(10).permutation(len(nodes))]
    np.testing.assert_array_equal(compiled.slabs(shuffled, 2, min_elements=16), [0, len(nodes)])
    small = compiled.slabs(nodes, 2, min_elements=len(nodes))  # too few elements to split
    np.testing.assert_array_equal(small, [0, len(nodes)])


@needs_numba
def test_assembly_outside_the_main_thread_is_serial_and_the_same():
    """numba's workqueue layer must not be entered from two threads at once: a body assembled in
    another thread takes the serial kernel, with the same K."""
    import threading
    space = _space("hex", 1)
    material, ev, reference = _state(space)
    body = HyperelasticBody(space, material, kernel="compiled")
    body._compiled.__dict__["bounds"] = compiled.slabs(space.element_nodes, 2, min_elements=2)
    out = {}
    worker = threading.Thread(target=lambda: out.update(K=body.stiffness(ev)))
    worker.start()
    worker.join()
    assert abs(out["K"] - reference).max() <= 1e-12 * abs(reference).max()


@needs_numba
@pytest.mark.parametrize("value", ["0", "two", "999"])
def test_bad_assembly_thread_count_names_the_variable_and_range(monkeypatch, value):
    from vlab import settings

    monkeypatch.setenv("VLAB_ASSEMBLY_THREADS", value)
    with pytest.raises(ValueError, match=r"VLAB_ASSEMBLY_THREADS must be an integer from 1 to"):
        settings.Settings.from_environment()
    from typer.testing import CliRunner

    from vlab.cli import app
    refused = CliRunner().invoke(app, ["info"])
    assert refused.exit_code == 2 and "invalid environment" in refused.output
    assert "VLAB_ASSEMBLY_THREADS must be an integer from 1 to" in refused.output
    assert jit.threads(settings.Settings(assembly_threads=1)) == 1
    with settings.using(settings.Settings(assembly_threads=1)):  # a body built under them assembles in one
        assert HyperelasticBody(_space("hex", 1), make_material("linear", 5.0, 2.0))._compiled.threads == 1


def test_vlab_kernel_numpy_keeps_numba_out(tmp_path):
    """VLAB_KERNEL=numpy: numba is not even imported, the numpy kernels assemble."""
    import os
    import subprocess
    import sys
    code = ("import sys; from vlab import settings; from vlab.fe import compiled; s = settings.current(); "
            "print(compiled.available(s), compiled.kernel_in_use(s), 'numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env=os.environ | {"VLAB_KERNEL": "numpy"}).stdout.split()
    assert out == ["False", "numpy", "False"]


def test_unknown_kernel_name_is_refused():
    with pytest.raises(ValueError, match="kernel must be"):
        HyperelasticBody(_space("tet", 1), make_material("linear", 5.0, 2.0), kernel="fast")


def test_the_cli_fills_the_settings_from_its_flags_over_the_environment(monkeypatch):
    from typer.testing import CliRunner

    from vlab import settings
    from vlab.cli import app

    monkeypatch.setenv("VLAB_LINEAR_SOLVER", "superlu")
    monkeypatch.setenv("VLAB_KERNEL", "auto")
    before = settings.current()
    try:
        out = CliRunner().invoke(app, ["--kernel", "numpy", "--threads", "1", "moduli", "--E", "10", "--nu", "0.3"])
        assert out.exit_code == 0, out.output
        assert settings.current() == settings.Settings(kernel="numpy", assembly_threads=1, linear_solver="superlu")
        bad = CliRunner().invoke(app, ["--linear-solver", "cholmod", "moduli", "--E", "10", "--nu", "0.3"])
        assert bad.exit_code == 2 and "VLAB_LINEAR_SOLVER must be one of" in bad.output
    finally:
        settings.use(before)


def test_run_scene_applies_its_settings_for_that_run_only():
    from helpers_scenes import block_scene

    from vlab import settings
    from vlab.run import run_scene

    before = settings.current()
    result = run_scene(block_scene("neo-hookean", 1.05, steps=2), settings=settings.Settings(kernel="numpy"))
    assert result.diagnostics.tangent_kernel == "numpy" and settings.current() == before


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize("model", ["mooney-rivlin", "yeoh", "gent", "arruda-boyce", "ogden"])
def test_the_rubber_models_assemble_the_textbook_stiffness_with_either_kernel(model, kernel):
    """The compiled kernel sums the rubber models' isotropic forms (tangent_forms: invariant
    models 3 or 5, Ogden 9 in its principal basis); the numpy kernel pulls back their terms
    (invariant models) or contracts the full tangent (Ogden)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).parent))
    from rubber_cards import law

    space = _space("hex", 1)
    material = law(model)
    body = HyperelasticBody(space, material, kernel=kernel)
    ev = body.evaluate(0.05 * np.random.default_rng(4).standard_normal(space.n_dofs))
    textbook = np.einsum("eqaJ,iJkLeq,eqbL,eq->ikeab", space.dN, material.tangent(ev.F), space.dN,
                         space.dx)
    K_full = body.pattern.matrix(np.ascontiguousarray(textbook))
    assert abs(body.stiffness(ev) - K_full).max() <= 1e-11 * abs(K_full).max()


@needs_numba
def test_a_body_assembles_under_the_settings_passed_to_it_not_the_installed_ones():
    from vlab import settings

    space, material = _space("hex", 1), make_material("linear", 5.0, 2.0)
    with settings.using(settings.Settings(kernel="auto")):
        assert HyperelasticBody(space, material, settings=Settings(kernel="numpy")).tangent_kernel == "numpy"
        assert HyperelasticBody(space, material, settings=Settings(assembly_threads=1))._compiled.threads == 1
    with settings.using(settings.Settings(kernel="numpy")):
        assert HyperelasticBody(space, material, settings=Settings()).tangent_kernel.startswith("compiled")


def test_jit_reads_no_installed_settings_its_callers_pass_them():
    import ast
    from pathlib import Path

    tree = ast.parse(Path(jit.__file__).read_text(encoding="utf-8"))
    calls = [n.func.attr for n in ast.walk(tree) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)]
    assert "current" not in calls and "from_environment" not in calls
