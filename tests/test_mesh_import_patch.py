"""Patch test on distorted imported meshes (issue #16, item 10): every imported cell type (tet,
hex), orders 1 and 2, from .vtu and .msh. With ν = 0 between clamped grips the homogeneous state
F = diag(λ, 1, 1) is exact (P = μ (F − F⁻ᵀ) has P22 = P33 = 0 there), so the load cell must read
μ (λ − 1/λ) A and the extensometer λ − 1 to round-off, whatever the mesh's distortion; a grip
that misses a node of its face (the 27-node hexahedron's face centres) does not."""

from pathlib import Path

import meshio
import numpy as np
import pytest

from vlab.geometry.block import block_specimen
from vlab.run import run_scene
from vlab.scene import parse_scene

SIZE = (20.0, 5.0, 5.0)
H = 2.5  # mesh size, mm: 8 x 2 x 2 hexahedra (x 6 tetrahedra), one line of interior nodes
E, STRETCH = 10.0, 1.5
VTK_FROM_SKFEM = [0, 3, 6, 2, 1, 5, 7, 4]  # inverse of vlab.geometry.imported._HEX_FROM_VTK


def distorted_mesh(cell: str, seed: int = 16):
    """vlab's block mesh with every node moved: interior nodes in x, y, z, boundary nodes along x
    only (the lateral faces stay planes, their normals ⟂ x), the end faces x = 0, L untouched."""
    mesh = block_specimen(SIZE, H, cell).mesh
    p, rng = mesh.p.copy(), np.random.default_rng(seed)
    lo, hi = p.min(axis=1, keepdims=True), p.max(axis=1, keepdims=True)
    ends = (np.abs(p[0] - lo[0]) < 1e-9) | (np.abs(p[0] - hi[0]) < 1e-9)
    interior = np.all((p > lo + 1e-9) & (p < hi - 1e-9), axis=0)
    p[0, ~ends] += 0.3 * rng.uniform(-1, 1, (~ends).sum())
    p[1:, interior] += 0.15 * rng.uniform(-1, 1, (2, interior.sum()))
    return type(mesh)(p, mesh.t)


def end_faces(mesh):
    facets = mesh.facets[:, mesh.boundary_facets()]
    x = mesh.p[0, facets].mean(axis=0)
    return facets[:, np.abs(x) < 1e-9].T, facets[:, np.abs(x - SIZE[0]) < 1e-9].T


def write(path: Path, cell: str) -> Path:
    mesh = distorted_mesh(cell)
    volume = ("tetra", mesh.t.T) if cell == "tet" else ("hexahedron", mesh.t.T[:, VTK_FROM_SKFEM])
    if path.suffix == ".vtu":  # grips as point-data arrays
        x = mesh.p[0]
        meshio.write(path, meshio.Mesh(mesh.p.T, [volume], point_data={
            "grip_left": (np.abs(x) < 1e-9).astype(np.int32),
            "grip_right": (np.abs(x - SIZE[0]) < 1e-9).astype(np.int32)}))
        return path
    left, right = end_faces(mesh)
    face = "triangle" if cell == "tet" else "quad"
    tags = [np.full(len(left), 1), np.full(len(right), 2), np.full(mesh.nelements, 3)]
    meshio.write(path, meshio.Mesh(mesh.p.T, [(face, left), (face, right), volume],
                                   cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
                                   field_data={"grip_left": np.array([1, 2]), "grip_right": np.array([2, 2]),
                                               "body": np.array([3, 3])}),
                 file_format="gmsh22", binary=False)
    return path


def scene(path: Path, order: int):
    return parse_scene({
        "name": "patch",
        "specimen": {"shape": "mesh", "file": str(path), "grips": {"left": "grip_left", "right": "grip_right"},
                     "axis": "x", "gauge_marks": [[5.0, 2.5, 5.0], [15.0, 2.5, 5.0]],
                     "transverse_marks": [[10.0, 0.0, 2.5], [10.0, 5.0, 2.5]],
                     "thickness_marks": [[10.0, 2.5, 0.0], [10.0, 2.5, 5.0]], "area": SIZE[1] * SIZE[2]},
        "mesh": {"order": order, "min_quality": 0.01},
        "material": {"model": "neo-hookean", "E": E, "nu": 0.0},
        "test": {"kind": "uniaxial", "grips": "clamped", "stretch": STRETCH, "steps": 2},
        "solver": {"rtol": 1e-12}})


@pytest.mark.parametrize("suffix", [".vtu", ".msh"])
@pytest.mark.parametrize("cell", ["tet", "hex"])
@pytest.mark.parametrize("order", [1, 2])
def test_a_distorted_imported_mesh_passes_the_patch_test_to_round_off(tmp_path, suffix, cell, order):
    result = run_scene(scene(write(tmp_path / f"patch{suffix}", cell), order))
    assert result.converged, result.history.failure
    mu = E / 2  # nu = 0
    exact = mu * (STRETCH - 1 / STRETCH) * SIZE[1] * SIZE[2]  # N
    c = result.curve
    assert c.force[0][-1] == pytest.approx(exact, rel=1e-9)
    assert c.strain[0][-1] == pytest.approx(STRETCH - 1.0, rel=1e-9)
    assert abs(c.transverse_strain[-1]) < 1e-9 and abs(c.thickness_strain[-1]) < 1e-9


def test_a_grip_face_of_27_node_hexahedra_holds_its_face_centre_nodes(tmp_path):
    """Each grip face of 2 x 2 quadrilaterals has 5 x 5 = 25 order-2 nodes (vertices, edge
    midpoints and the 4 face centres), all clamped: 3 x 25 DOFs per grip."""
    from vlab.fe.space import DisplacementSpace
    from vlab.loading.grips import grip_loading
    from vlab.run import build_specimen

    sc = scene(write(tmp_path / "patch.vtu", "hex"), 2)
    specimen = build_specimen(sc)
    X = DisplacementSpace.build(specimen.mesh, 2).node_coordinates
    for grip in specimen.grips:
        assert grip.select(X).sum() == 5 * 5
    loading = grip_loading(specimen, X, (STRETCH,), "clamped")
    assert len(loading.prescribed) == 2 * 3 * 25
