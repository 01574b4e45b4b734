"""Meshes are checked before solving; valid but distorted meshes still give the right answer."""

import dataclasses

import numpy as np
import pytest
import skfem

from helpers_scenes import block_scene
from vlab.geometry.block import block_mesh
from vlab.geometry.perturb import perturbed
from vlab.geometry.mesh_check import MeshError, check_mesh, element_quality
from vlab.report.results import result_to_dict
from vlab.run import MeshQualityError, build_specimen, run_scene


def test_structured_meshes_pass_and_score_their_shape():
    for cell in ("hex", "tet"):
        mesh = block_mesh((40.0, 10.0, 1.0), 10.0, cell)  # 10:10:1 cells: high aspect ratio
        check_mesh(mesh)
        q = element_quality(mesh)
        assert q.min() > 0.5  # 0.87 (tet needles), 1 (hex)


def test_unused_and_duplicate_nodes_are_errors():
    mesh = block_mesh((2.0, 2.0, 2.0), 1.0, "hex")
    extra = skfem.MeshHex(np.hstack([mesh.p, [[5.0], [5.0], [5.0]]]), mesh.t)
    with pytest.raises(MeshError, match="1 unused node"):
        check_mesh(extra)
    # split the mesh along x = 1 by giving the second layer its own copy of the shared nodes
    p, t = mesh.p.copy(), mesh.t.copy()
    shared = np.flatnonzero(np.isclose(p[0], 1.0))
    copies = np.arange(p.shape[1], p.shape[1] + len(shared))
    right = np.all(p[0, t] >= 1.0 - 1e-12, axis=0)
    remap = np.arange(p.shape[1])
    remap[shared] = copies
    t[:, right] = remap[t[:, right]]
    with pytest.raises(MeshError, match="duplicate nodes"):
        check_mesh(skfem.MeshHex(np.hstack([p, p[:, shared]]), t))


def test_inverted_hexahedron_and_flat_tetrahedron_are_errors():
    hexa = block_mesh((1.0, 1.0, 1.0), 1.0, "hex")
    p = hexa.p.copy()
    top = np.flatnonzero(p[2] == 1.0)
    p[2, top[0]] = -0.5  # push one top corner through the bottom face
    with pytest.raises(MeshError, match="inverted or degenerate element"):
        check_mesh(skfem.MeshHex(p, hexa.t))
    sliver = skfem.MeshTet(np.array([[0.0, 1.0, 0.0, 0.5], [0.0, 0.0, 1.0, 0.5], [0.0, 0.0, 0.0, 0.0]]),
                           np.array([[0], [1], [2], [3]]))
    with pytest.raises(MeshError, match="degenerate"):
        check_mesh(sliver)
    nearly_flat = sliver.p.copy()
    nearly_flat[2, 3] = 0.01
    with pytest.raises(MeshError, match="sliver"):
        check_mesh(skfem.MeshTet(nearly_flat, sliver.t))


def test_a_bad_mesh_stops_the_run_before_solving():
    scene = block_scene("neo-hookean", 1.2)
    spec = build_specimen(scene)
    p = spec.mesh.p.copy()
    inner = np.flatnonzero(np.all((p > 1e-9) & (p < 10 - 1e-9), axis=0))
    p[:, inner[0]] = [0.0 + 12.0, 5.0, 5.0]  # drag an interior node outside: elements invert
    with pytest.raises(MeshQualityError, match="invalid mesh: .*invert"):
        run_scene(scene, specimen=dataclasses.replace(spec, mesh=type(spec.mesh)(p, spec.mesh.t)))


@pytest.mark.parametrize("cell", ["hex", "tet"])
def test_randomly_perturbed_mesh_passes_the_patch_test(cell):
    """Roller grips deform the block homogeneously, and a homogeneous (linear) field is exact on
    any valid mesh: the perturbed mesh must match the analytic curve to solver tolerance."""
    scene = block_scene("neo-hookean", 1.6, cell=cell, size=2.5, steps=4)
    spec = perturbed(build_specimen(scene), 0.2, seed=1)
    check_mesh(spec.mesh)  # valid, but no longer a regular grid
    assert element_quality(spec.mesh).min() < 0.9  # it really is distorted
    data = result_to_dict(run_scene(scene, specimen=spec))
    regular = result_to_dict(run_scene(scene))
    assert data["converged"]
    assert data["reference"]["max_relative_error_x"] < 1e-6  # measured: 4e-15
    # the fitted E and nu are those of the regular mesh (the fit's own bias is mesh-independent)
    assert data["measured"]["E"] == pytest.approx(regular["measured"]["E"], rel=1e-8)
    assert data["measured"]["nu"] == pytest.approx(regular["measured"]["nu"], rel=1e-8)


@pytest.mark.parametrize("cell", ["hex", "tet"])
def test_high_aspect_ratio_cells_pass_the_patch_test(cell):
    scene = block_scene("neo-hookean", 1.6, cell=cell, size=10.0, steps=4, extent=(40.0, 10.0, 1.0))
    data = result_to_dict(run_scene(scene))
    assert data["converged"] and data["reference"]["max_relative_error_x"] < 1e-6


@pytest.mark.parametrize("cell", ["hex", "tet"])
def test_perturbed_mesh_of_a_clamped_block_stays_close_to_the_regular_mesh(cell):
    """Clamped grips make the field non-uniform; distortion changes the discretisation error
    only: the grip force of a 20 % distorted mesh stays within 0.5 % of the regular one
    (measured: 0.014 % hex, 0.11 % tet)."""
    scene = block_scene("neo-hookean", 1.3, grips="clamped", cell=cell, size=2.5, steps=3)
    regular = result_to_dict(run_scene(scene))
    moved = result_to_dict(run_scene(scene, specimen=perturbed(build_specimen(scene), 0.2, seed=2)))
    assert regular["converged"] and moved["converged"]
    f0, f1 = regular["curve"]["force"][-1], moved["curve"]["force"][-1]
    assert abs(f1 - f0) / f0 < 0.005


@pytest.mark.parametrize("seed", range(6))
def test_close_pairs_are_cKDTrees_pairs(seed):
    from scipy.spatial import cKDTree

    from vlab.geometry.mesh_check import close_pairs

    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.arange(7.0)] * 3, indexing="ij"), -1).reshape(-1, 3)
    planted = grid[rng.choice(len(grid), 25)] + rng.uniform(-1, 1, (25, 3)) * 1e-10  # near copies
    triple = np.repeat(grid[[3]], 3, axis=0)                                          # a cluster of 4
    points = np.vstack([grid, planted, triple, rng.uniform(0, 6, (300, 3))])[rng.permutation(len(grid) + 328)]
    dim = 3 if seed % 2 == 0 else 2  # 2D meshes too
    pts = points[:, :dim]
    for tol in (1e-9, 1e-3, 0.3):
        expected = cKDTree(pts).query_pairs(tol, output_type="ndarray")
        expected = np.sort(expected, axis=1) if len(expected) else expected.reshape(0, 2)
        expected = expected[np.lexsort((expected[:, 1], expected[:, 0]))]
        assert np.array_equal(close_pairs(pts, tol), expected)
