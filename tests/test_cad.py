"""shape = "cad": a Gmsh .geo (or STEP) specimen meshed by Gmsh, grips by physical group or box,
errors that name the field. (E and ν of the shipped CAD dumb-bell within 0.5 %: test_specimen_files.)"""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from vlab.geometry.cad import gmsh_version
from vlab.scene import SceneError, apply_overrides, parse_scene

pytestmark = pytest.mark.skipif(gmsh_version() is None, reason="the 'cad' extra (gmsh) is not installed")
SCENE = Path(__file__).resolve().parents[1] / "specimens" / "dogbone-cad-1a.toml"


def raw(**overrides):
    return apply_overrides(tomllib.loads(SCENE.read_text(encoding="utf-8")), {"mesh.size": 8.0, "mesh.order": 1} | overrides)


def parse(data):
    return parse_scene(data, origin=SCENE.name, base_dir=SCENE.parent)


def test_gmsh_meshes_the_geo_into_tetrahedra_that_pass_the_mesh_checks():
    from vlab.run import build_specimen, checked_quality

    scene = parse(raw())
    assert scene.specimen.shape == "cad" and scene.specimen.data.cell == "tet"
    extent = scene.specimen.extent
    assert extent == pytest.approx([170.0, 20.0, 4.0], abs=1e-6)  # the drawing's outline and thickness
    quality = checked_quality(scene, build_specimen(scene))
    assert quality.min_quality >= scene.mesh.min_quality and quality.mean_quality > 0.6  # Gmsh: ~0.8 mean ratio


def test_grips_given_as_boxes_select_the_same_tabs_as_the_physical_groups():
    by_name = parse(raw()).specimen.data
    boxes = raw(**{"specimen.grips": {"left": {"min": [-86, -11, -1], "max": [-60, 11, 5]},
                                      "right": {"min": [60, -11, -1], "max": [86, 11, 5]}}})
    by_box = parse(boxes).specimen.data
    tab = by_name.points[by_name.regions["grip_left"]]
    box = by_box.points[by_box.regions["box:left"]]
    assert box[:, 0].max() == pytest.approx(-60.0) and tab[:, 0].max() == pytest.approx(-60.0)
    assert len(box) >= len(tab)  # the box also takes the tab's side faces and interior
    assert np.all(box[:, 0] <= -60.0 + 1e-9)


@pytest.mark.parametrize("overrides, message", [
    ({"specimen.grips": {"left": "grip_left", "right": "tab"}}, "'tab' is not a physical group.*grip_right"),
    ({"specimen.file": "cad/missing.geo"}, "specimen.file.*does not exist"),
    ({"specimen.file": "meshes/bar.msh"}, "specimen.file must be a Gmsh .geo, STEP"),
    ({"mesh.cell": "hex"}, "mesh.cell must be 'tet' for specimen.shape = 'cad'"),
    ({"specimen.grips": {"left": {"min": [0, 0, 0], "max": [-1, 1, 1]}, "right": "grip_right"}},
     "min .* must be below max"),
])
def test_bad_cad_input_names_the_field(overrides, message):
    with pytest.raises(SceneError, match=message):
        parse(raw(**overrides))


DOGBONE = Path(__file__).resolve().parents[1] / "specimens" / "dogbone-iso527-2-1a.toml"


def dogbone(**overrides):
    raw = tomllib.loads(DOGBONE.read_text(encoding="utf-8"))
    return parse_scene(apply_overrides(raw, {"mesh.cell": "tet", "mesh.mesher": "gmsh"} | overrides),
                       origin=DOGBONE.name, base_dir=DOGBONE.parent)


def test_gmsh_tetrahedra_of_a_dogbone_recover_E_and_nu_within_half_a_percent():
    """Run in a subprocess: a PARDISO solve of this mesh starts MKL's GNU OpenMP pool, after which a
    forked child (the session's comparison fixture) deadlocks in libgomp (measured)."""
    import json
    import subprocess
    import sys
    import textwrap

    script = textwrap.dedent(f"""
        import json, tomllib
        import numpy as np
        from vlab.run import run_scene
        from vlab.scene import apply_overrides, parse_scene
        raw = apply_overrides(tomllib.loads(open({str(DOGBONE)!r}).read()), {{"mesh.cell": "tet", "mesh.mesher": "gmsh",
              "mesh.size": 8.0, "material.model": "linear", "test.stretch": 1.01, "test.steps": 2}})
        scene = parse_scene(raw, base_dir={str(DOGBONE.parent)!r})
        r = run_scene(scene)
        d = scene.specimen.dimensions
        x = r.specimen.mesh.p[0]
        print(json.dumps({{"mesh": type(r.specimen.mesh).__name__, "converged": r.converged, "E": r.constants.E,
                          "nu": r.constants.nu, "at_grips": [int(np.isclose(x, d.grip_length).sum()),
                          int(np.isclose(x, d.overall_length - d.grip_length).sum())]}}))
    """)
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    found = json.loads(proc.stdout.strip().splitlines()[-1])
    assert found["mesh"].startswith("MeshTet") and found["converged"]
    assert min(found["at_grips"]) >= 4  # whole faces of nodes on the grip edges (the outline is cut there)
    assert found["E"] == pytest.approx(10.0, rel=0.005) and found["nu"] == pytest.approx(0.3, rel=0.005)


@pytest.mark.parametrize("overrides, message", [
    ({"mesh.cell": "hex"}, "mesh.mesher = 'gmsh' meshes a dogbone in tetrahedra.*'hex'"),
    ({"mesh.symmetry": "half"}, "mesh.mesher = 'gmsh'.*'half'"),
    ({"mesh.mesher": "netgen"}, "mesh.mesher"),
])
def test_the_gmsh_mesher_is_refused_where_it_does_not_apply(overrides, message):
    with pytest.raises(SceneError, match=message):
        dogbone(**overrides)


def test_the_cost_study_offers_a_gmsh_tetrahedra_family():
    from vlab.study.cost import CostOptions, knob_points

    points = knob_points(dogbone(**{"mesh.mesher": "vlab"}), CostOptions(levels=3, orders=(1,), cells=("tet", "gmsh-tet")))
    gmsh = [p for p in points if p.label["knob"] == "mesh size (order 1, gmsh-tet)"]
    assert len(gmsh) == 3 and all(p.source["mesh"]["mesher"] == "gmsh" and p.source["mesh"]["cell"] == "tet"
                                  for p in gmsh)
