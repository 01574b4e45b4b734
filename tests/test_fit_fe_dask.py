"""FE-in-the-loop solves on Dask (the sweeps' cluster path) give the in-process fit exactly."""

import subprocess
import sys
import tomllib

import numpy as np

from vlab.identify.fe_sensitivity import simulate

BLOCK = '''name = "fe-block-dask"
[specimen]
shape = "block"
size = [12.0, 4.0, 4.0]
[mesh]
size = 2.0
order = 1
cell = "hex"
[material]
model = "gent"
mu = 0.4
Jm = 8.0
K = 3.0
[test]
kind = "uniaxial"
grips = "clamped"
stretch = 1.5
steps = 4
'''
FIT = '''[model]
name = "gent"
[[data]]
file = "r.csv"
kind = "specimen"
[fe]
scene = "block.toml"
parameters = ["mu", "Jm"]
start = { mu = 0.6, Jm = 12.0 }
max_solves = 12
cache = false
'''


def _fit_file(tmp_path):
    (tmp_path / "block.toml").write_text(BLOCK)
    fe = {"scene_path": str(tmp_path / "block.toml"), "scene_raw": tomllib.loads(BLOCK), "parameters": ("mu",),
          "model": "gent", "volumetric": None}
    s = simulate(fe, {"mu": 0.4, "Jm": 8.0, "K": 3.0})
    F = s.force[:, 0] * (1 + 0.01 * np.random.default_rng(2).standard_normal(len(s.force)))
    (tmp_path / "r.csv").write_text("strain,force\n" + "".join(f"{e:.17g},{f:.17g}\n" for e, f in zip(s.strain[:, 0], F)))
    (tmp_path / "fit.toml").write_text(FIT)
    return tmp_path / "fit.toml"


def test_a_gent_fit_with_its_solves_on_a_local_dask_cluster_equals_the_in_process_fit(tmp_path):
    from vlab.identify.fe_loop import fit_specimen
    from vlab.identify.fitfile import load_fit
    from vlab.study.sweep import Execution

    spec = load_fit(_fit_file(tmp_path))
    here = fit_specimen(spec).data
    there = fit_specimen(spec, Execution(workers=1)).data
    assert here["converged"] and there["converged"]
    assert there["fe"]["execution"] == {"dask": True, "scheduler": None, "workers": 1, "tasks": there["fe"]["solves"]}
    assert here["fe"]["execution"] == {"dask": False}
    assert there["parameters"] == here["parameters"]  # bit for bit: the same solves, elsewhere
    assert [t["parameters"] for t in there["fe"]["trail"]] == [t["parameters"] for t in here["fe"]["trail"]]
    assert abs(here["parameters"]["Jm"] - 8.0) <= 3 * here["uncertainty"]["Jm"]["standard_error"]


def test_workers_for_a_fit_without_specimen_data_is_refused_with_exit_2(tmp_path):
    from pathlib import Path

    treloar = Path(__file__).resolve().parents[1] / "specimens" / "treloar1944" / "treloar-uniaxial.toml"
    r = subprocess.run([sys.executable, "-m", "vlab", "fit", str(treloar), "--out", str(tmp_path / "o"), "--workers", "2"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 2 and "no data set of kind = \"specimen\"" in r.stdout + r.stderr
    assert not (tmp_path / "o").exists()


def test_a_scheduler_that_does_not_answer_is_an_invalid_option_with_nothing_written(tmp_path):
    fit = _fit_file(tmp_path)
    r = subprocess.run([sys.executable, "-m", "vlab", "fit", str(fit), "--out", str(tmp_path / "o"),
                        "--scheduler", "tcp://127.0.0.1:1"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 2 and "invalid option" in r.stdout + r.stderr and "cannot connect" in r.stdout + r.stderr
    assert not (tmp_path / "o").exists()
