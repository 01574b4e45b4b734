"""The torsion and inflation benchmark against FElupe (benchmarks/kinds_felupe.py, issue 33) runs on
the package as it is, and both codes solve the same discrete problem: on the small meshes vlab's
and FElupe's torque, axial force and pressure at the end of the test agree to 1e-6 (FElupe is an
independent solver: its own elements, material law and Newton on vlab's exported mesh)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytest.importorskip("felupe", reason="FElupe (the bench/test extra) is not installed: no reference solver")


def _one(code: str, problem: str) -> dict:
    out = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "kinds_felupe.py"), "--one", code, problem],
                         capture_output=True, text=True, timeout=600, cwd=ROOT, env=os.environ.copy())
    assert out.returncode == 0, out.stderr[-2000:]
    line = [x for x in out.stdout.splitlines() if x.startswith("RESULT ")][-1]
    return json.loads(line[len("RESULT "):])


@pytest.mark.parametrize("problem, readings", [("torsion-small", ("torque", "axial_force")),
                                               ("inflation-small", ("pressure",))])
def test_vlab_and_felupe_agree_on_the_small_mesh(problem, readings):
    vlab, felupe = _one("vlab", problem), _one("felupe", problem)
    assert "error" not in vlab and "error" not in felupe, (vlab, felupe)
    assert vlab["dofs"] == felupe["dofs"] > 1000
    for name in readings:
        assert vlab[name] != 0.0
        assert vlab[name] == pytest.approx(felupe[name], rel=1e-6), name
