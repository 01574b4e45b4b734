"""The cube-scaling benchmark (benchmarks/cube_scaling.py) runs on the package as it is, and its
codes solve the same problem: on a 3³ cube vlab and the plain CG + AMG Newton reach the same grip
force (benchmarks are not run by the suite otherwise, so an API change would break them silently)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _one(code: str, n: int) -> dict:
    out = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "cube_scaling.py"), "--one", code, str(n)],
                         capture_output=True, text=True, timeout=600, cwd=ROOT, env=os.environ.copy())
    assert out.returncode == 0, out.stderr[-2000:]
    line = [x for x in out.stdout.splitlines() if x.startswith("RESULT ")][-1]
    return json.loads(line[len("RESULT "):])


def test_vlab_and_the_cg_amg_reference_reach_the_same_force_on_a_small_cube():
    vlab, amg = _one("vlab", 3), _one("amg", 3)
    assert vlab["dofs"] == amg["dofs"] == 192
    assert vlab["force"] == pytest.approx(amg["force"], rel=1e-7)
    assert vlab["path"] == "direct" and vlab["factorizations"] >= 1 and amg["factorizations"] == 0
