"""benchmarks/gmsh_tets.py (Gmsh tetrahedra against vlab's split-hex tetrahedra on the ISO 527-2 1A
dumb-bell) runs, and on its coarse pair both meshers recover E and ν: the cost study of the README
stays reproducible. In a subprocess: Gmsh and PARDISO load OpenMP runtimes that a later forked
worker of this session would inherit (see test_cad)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from vlab.geometry.cad import gmsh_version

pytestmark = pytest.mark.skipif(gmsh_version() is None, reason="the 'cad' extra (gmsh) is not installed")
ROOT = Path(__file__).resolve().parents[1]
TOLERANCE = 0.005  # E of the two meshes, relative to each other and to the input (linear, 0.5 %)


def test_the_gmsh_against_split_hex_benchmark_runs_and_both_meshes_give_E_within_half_a_percent():
    proc = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "gmsh_tets.py"), "--coarse"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    rows = {r["mesher"]: r for r in json.loads(proc.stdout.strip().splitlines()[-1])}
    gmsh, vlab = rows["Gmsh"], rows["vlab split hex"]
    assert gmsh["status"] == vlab["status"] == "ok"
    # the two families are different meshes (mesh.mesher = "gmsh" reaches the dogbone's mesher)
    assert gmsh["dofs"] != vlab["dofs"] and gmsh["quality"] > vlab["quality"] + 0.2
    assert gmsh["E"] == pytest.approx(vlab["E"], rel=TOLERANCE)
    for r in (gmsh, vlab):
        assert r["E"] == pytest.approx(10.0, rel=TOLERANCE) and r["nu"] == pytest.approx(0.3, rel=TOLERANCE)
    assert "| Gmsh | 1 | 8 |" in proc.stdout  # the printed table
