"""Identification from full fields (vlab fit kind = "field"): Neo-Hookean μ recovered from images
rendered by the virtual camera and correlated by vlab's DIC, exact sensitivities, bad input."""

import importlib.util
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from vlab.fields import SceneError

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "specimens" / "dic-field-fit"
MU = 0.4  # block-clamped.toml's mu: the constant the images were made with


def _generator():
    spec = importlib.util.spec_from_file_location("make_field_data", EXAMPLE / "make_field_data.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _fit_file(folder: Path, start: float, fields: str = "field", scene: str | None = None) -> Path:
    """fit.toml in folder: mu of ``scene`` (default: a copy of the example's block) from ``start``."""
    if scene is None:
        scene = "block-clamped.toml"
        shutil.copy(EXAMPLE / scene, folder / scene)
    path = folder / "fit.toml"
    path.write_text(f'''name = "field"
[model]
name = "neo-hookean"
[[data]]
kind = "field"
fields = "{fields}"
[fe]
scene = "{scene}"
parameters = ["mu"]
start = {{ mu = {start} }}
max_solves = 12
cache = false
''')
    return path


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    """A folder of noise-free 16-bit images' fields (rendered and correlated here)."""
    folder = tmp_path_factory.mktemp("clean")
    camera = dict(_generator().CAMERA, noise=0.0)
    _generator().write_folder(folder / "field", EXAMPLE / "block-clamped.toml", camera)
    return folder


def _fit(path: Path):
    from vlab.identify.fitfile import load_fit
    from vlab.identify.fitting import fit_one

    return fit_one(load_fit(path)).data


def test_mu_from_noise_free_images_within_1_percent_from_a_30_percent_high_start(clean):
    d = _fit(_fit_file(clean, 1.3 * MU))
    mu = d["parameters"]["mu"]
    print(f"noise-free: mu = {mu:.6g} ± {d['uncertainty']['mu']['standard_error']:.2g}, error {mu / MU - 1:+.3%}, "
          f"solves {d['fe']['solves']}, fit {d['timing']['fit_s']:.3g} s")
    assert d["converged"] and abs(mu / MU - 1) < 0.01
    u = d["uncertainty"]["mu"]
    assert u["interval"] is not None and u["standard_error"] > 0 and np.isfinite(u["standard_error"])


DIC_TABLE = """
[instruments.dic]
face = "top"
subset = 25
step = 8
strain_window = 5
[instruments.dic.camera]
pixels = [400, 136]
mm_per_px = 0.025
noise = 0.01
seed = 5
[instruments.dic.speckle]
size = 4.0
"""


def test_mu_from_vlab_runs_own_dic_folder_at_1_percent_grey_noise(tmp_path):
    """vlab run of the scene with [instruments.dic] writes <report>/dic (its camera, noise floor,
    fields and levels); vlab fit reads that folder as it is."""
    scene = tmp_path / "scene.toml"
    scene.write_text((EXAMPLE / "block-clamped.toml").read_text() + DIC_TABLE)
    run = subprocess.run([sys.executable, "-m", "vlab", "run", str(scene), "--out", str(tmp_path / "run"), "--no-estimate"],
                         capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    fit = _fit_file(tmp_path, 0.7 * MU, fields="run/dic", scene="scene.toml")
    r = subprocess.run([sys.executable, "-m", "vlab", "fit", str(fit), "--out", str(tmp_path / "out")],
                       capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    d = json.loads((tmp_path / "out" / "fit.json").read_text())
    mu, row = d["parameters"]["mu"], d["datasets"][0]
    floor = json.loads((tmp_path / "run" / "dic" / "dic.json").read_text())["noise_floor"]
    print(f"1 % grey noise (vlab run's dic/): mu = {mu:.6g} ± {d['uncertainty']['mu']['standard_error']:.2g}, "
          f"error {mu / MU - 1:+.3%}, strain rms {row['strain_rms']:.3g}, sigma_E {row['strain_noise']:.3g}, "
          f"solves {d['fe']['solves']}, fit {d['timing']['fit_s']:.3g} s")
    assert abs(mu / MU - 1) < 0.01
    assert row["strain_noise"] == pytest.approx(1e-6 * max(floor["sigma_exx_microstrain"], floor["sigma_eyy_microstrain"]))
    lo, hi = d["uncertainty"]["mu"]["interval"]
    assert lo < mu < hi
    assert (tmp_path / "out" / "field.png").is_file() and "full fields" in (tmp_path / "out" / "index.html").read_text()


def test_the_residuals_sensitivity_is_the_whole_test_difference(clean):
    from vlab.identify.field_fit import _Problem
    from vlab.identify.fitfile import load_fit

    prob = _Problem(load_fit(_fit_file(clean, MU)))
    r, J, _ = prob.evaluate([0.45])
    h = 1e-5
    fd = (prob.evaluate([0.45 + h])[0] - prob.evaluate([0.45 - h])[0]) / (2 * h)
    assert np.max(np.abs(J[:, 0] - fd)) <= 1e-6 * np.max(np.abs(fd))
    strain = J[:-4, 0]  # the last four rows are the load cell's
    assert np.max(np.abs(strain)) > 0.01 * np.max(np.abs(J[-4:, 0]))  # the strain maps do move with mu


def _copy(clean: Path, tmp_path: Path) -> Path:
    shutil.copytree(clean / "field", tmp_path / "field")
    return tmp_path / "field"


def test_bad_folders_name_the_file_row_and_column(clean, tmp_path):
    from vlab.identify.fitfile import load_fit

    field = _copy(clean, tmp_path)
    fit = _fit_file(tmp_path, MU)
    levels = (field / "levels.csv").read_text()
    (field / "levels.csv").write_text(levels.replace("level-2,", "level-9,"))
    with pytest.raises(SceneError, match=r"levels.csv row 3 column 'image': 'level-9' has no field file"):
        load_fit(fit)
    (field / "levels.csv").write_text(levels.replace("force", "load"))
    with pytest.raises(SceneError, match=r"levels.csv: missing column 'force'"):
        load_fit(fit)
    (field / "levels.csv").write_text(levels)
    csv = (field / "fields" / "level-3.csv").read_text().splitlines()
    csv[5] = csv[5].replace(",ok", ",ok").split(",", 1)[0] + ",x" + "," + csv[5].split(",", 2)[2]
    (field / "fields" / "level-3.csv").write_text("\n".join(csv) + "\n")
    with pytest.raises(SceneError, match=r"level-3.csv row 6 column 'y_px': 'x' is not a number"):
        load_fit(fit)
    (field / "dic.json").write_text(json.dumps({"settings": {"strain_window": 5, "subset": 25}}))
    with pytest.raises(SceneError, match=r"camera.pixels is missing"):
        load_fit(fit)


def test_a_camera_that_puts_subsets_off_the_face_is_refused_with_exit_2(clean, tmp_path):
    field = _copy(clean, tmp_path)
    d = json.loads((field / "dic.json").read_text())
    d["camera"]["centre_mm"][1] += 1.5  # across the 4 mm face: the top rows map 0.8 mm beyond its edge
    (field / "dic.json").write_text(json.dumps(d))
    fit = _fit_file(tmp_path, MU)
    r = subprocess.run([sys.executable, "-m", "vlab", "fit", str(fit), "--out", str(tmp_path / "out")],
                       capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert r.returncode == 2, r.stdout + r.stderr
    assert "off the FE face" in r.stderr + r.stdout and "columns 'x_px', 'y_px'" in r.stderr + r.stdout
    assert not (tmp_path / "out").exists()
