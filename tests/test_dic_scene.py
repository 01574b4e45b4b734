"""[instruments.dic] in a scene: parsing (every bad value a SceneError naming the field, exit 2 and
nothing written), a scene without the table untouched, and an end-to-end run of a small dogbone
whose DIC virtual extensometer agrees with the point extensometers and whose DIC agrees with the
FE field levelled through the same subsets and strain window."""

from __future__ import annotations

import copy
import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from vlab.cli import app
from vlab.scene import SceneError, parse_scene
from vlab.scene.file import parse_toml

ROOT = Path(__file__).resolve().parents[1]
SPECIMEN = ROOT / "specimens" / "dogbone-dic.toml"


def _source() -> dict:
    return parse_toml(SPECIMEN.read_text(encoding="utf-8"), str(SPECIMEN))


def _with(path: tuple, value) -> dict:
    src = copy.deepcopy(_source())
    table = src
    for key in path[:-1]:
        table = table.setdefault(key, {})
    table[path[-1]] = value
    return src


BAD = [
    (("instruments", "dic", "face"), "side", "instruments.dic.face"),
    (("instruments", "dic", "subset"), 20, "instruments.dic.subset"),
    (("instruments", "dic", "subset"), 5, "instruments.dic.subset"),
    (("instruments", "dic", "strain_window"), 4, "instruments.dic.strain_window"),
    (("instruments", "dic", "step"), 0, "instruments.dic.step"),
    (("instruments", "dic", "tolerance"), 0.5, "instruments.dic.tolerance"),
    (("instruments", "dic", "min_zncc"), 1.0, "instruments.dic.min_zncc"),
    (("instruments", "dic", "interpolation"), "linear", "instruments.dic.interpolation"),
    (("instruments", "dic", "shape_function"), "quadratic", "instruments.dic.shape_function"),
    (("instruments", "dic", "metrics"), "fast", "instruments.dic.metrics"),
    (("instruments", "dic", "lens"), 50, "instruments.dic"),
    (("instruments", "dic", "camera", "pixels"), [512], "instruments.dic.camera.pixels"),
    (("instruments", "dic", "camera", "pixels"), [8, 256], "instruments.dic.camera.pixels[0]"),
    (("instruments", "dic", "camera", "field_of_view"), -1.0, "instruments.dic.camera.field_of_view"),
    (("instruments", "dic", "camera", "mm_per_px"), 0.05, "mm_per_px"),  # both scales given
    (("instruments", "dic", "camera", "bit_depth"), 12, "instruments.dic.camera.bit_depth"),
    (("instruments", "dic", "camera", "noise"), 0.7, "instruments.dic.camera.noise"),
    (("instruments", "dic", "camera", "blur"), -0.1, "instruments.dic.camera.blur"),
    (("instruments", "dic", "camera", "supersample"), 9, "instruments.dic.camera.supersample"),
    (("instruments", "dic", "camera", "seed"), -1, "instruments.dic.camera.seed"),
    (("instruments", "dic", "camera", "centre"), [1.0], "instruments.dic.camera.centre"),
    (("instruments", "dic", "camera", "background"), 2.0, "instruments.dic.camera.background"),
    (("instruments", "dic", "speckle", "size"), 0.5, "instruments.dic.speckle.size"),
    (("instruments", "dic", "speckle", "density"), 0.0, "instruments.dic.speckle.density"),
    (("instruments", "dic", "speckle", "seed"), 1.5, "instruments.dic.speckle.seed"),
    (("instruments", "dic", "subset"), 301, "instruments.dic.subset"),
    (("instruments", "camera"), {}, "instruments"),
]


@pytest.mark.parametrize("path, value, field", BAD, ids=[".".join(p[0][1:]) + f"={p[1]!r}" for p in BAD])
def test_a_bad_value_names_its_field(path, value, field):
    with pytest.raises(SceneError, match=field.replace(".", r"\.").replace("[", r"\[")):
        parse_scene(_with(path, value))


def test_a_subset_larger_than_the_image_is_refused():
    src = _with(("instruments", "dic", "camera", "pixels"), [512, 42])
    src["instruments"]["dic"]["subset"] = 41
    with pytest.raises(SceneError, match=r"instruments\.dic\.subset = 41 px does not fit.*pixels"):
        parse_scene(src)


def test_the_parser_allows_what_the_engine_accepts():
    """The scene's lists are written out (parsing imports none of vlab.dic): they must match."""
    from vlab.dic import icgn
    from vlab.dic.correlate import Settings
    from vlab.scene.instruments import INTERPOLATIONS, SETTINGS_KEYS

    assert INTERPOLATIONS == tuple(icgn.ORDERS)
    assert set(SETTINGS_KEYS) == set(Settings.__dataclass_fields__)


def _scene_file(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("extra, message", [
    ("subset = 20\n", "instruments.dic.subset"),
    ("[instruments.dic.camera]\n", None),  # duplicate table: a TOML error, still exit 2
])
def test_cli_refuses_a_bad_table_with_exit_2_and_writes_nothing(tmp_path, extra, message):
    text = SPECIMEN.read_text(encoding="utf-8").replace("subset = 21                   # px\n", extra) \
        if message else SPECIMEN.read_text(encoding="utf-8") + extra
    out = tmp_path / "report"
    result = CliRunner().invoke(app, ["run", str(_scene_file(tmp_path, text)), "--out", str(out), "--no-estimate", "-q"])
    assert result.exit_code == 2, result.output
    if message:
        assert message in result.output.replace("\n", "")
    assert not out.exists()


def test_a_camera_that_cannot_see_the_face_is_exit_2_before_the_solve(tmp_path):
    text = SPECIMEN.read_text(encoding="utf-8").replace("supersample = 2", "supersample = 2\ncentre = [200.0, 0.0]")
    out = tmp_path / "report"
    result = CliRunner().invoke(app, ["run", str(_scene_file(tmp_path, text)), "--out", str(out), "--no-estimate", "-q"])
    assert result.exit_code == 2, result.output
    assert "instruments.dic.camera.centre" in result.output.replace("\n", "") and "cannot see the face" in result.output
    assert not out.exists()


def test_a_scene_without_the_table_imports_no_dic():
    code = ("import sys; from vlab.scene import load_scene; "
            f"s = load_scene({str(ROOT / 'specimens' / 'dogbone-custom.toml')!r}); "
            f"d = load_scene({str(SPECIMEN)!r}); "
            "assert s.instruments is None and d.instruments.dic.face == 'top'; "
            "assert not [m for m in sys.modules if m.startswith('vlab.dic')], 'vlab.dic imported'")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)


# --- end to end -----------------------------------------------------------------------------------

# measured on this scene (the test's smaller camera: 320 x 128 px at 0.0625 mm/px, noise 0.001,
# blur 0.5 px, subset 21, step 6, window 5; 96 px across the gauge width): E_dic/E_point − 1 =
# −0.29 %, ν_dic/ν_point − 1 = +0.51 %; the specimen file's 512 × 256 px camera gives −0.14 % and
# +0.05 % (docs/dic.md). ν is the noisier: the transverse strain's lever is the gauge width.
E_TOLERANCE = 0.005
NU_TOLERANCE = 0.01


def _small_camera_scene(folder: Path) -> Path:
    """The specimen file with the test's smaller camera (320 × 128 px over 20 mm), in ``folder``."""
    text = SPECIMEN.read_text(encoding="utf-8")
    for old, new in (("pixels = [512, 256]", "pixels = [320, 128]"), ("field_of_view = 24.0", "field_of_view = 20.0")):
        assert old in text
        text = text.replace(old, new)
    path = folder / "scene.toml"
    path.write_text(text + "\n[measure]\nmodulus_points = 5\n", encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("dic-run")
    path = _small_camera_scene(folder)
    out = folder / "report"
    result = CliRunner().invoke(app, ["run", str(path), "--out", str(out), "--no-estimate", "--no-render", "-q"])
    assert result.exit_code == 0, result.output
    return out


def test_the_dic_virtual_extensometer_agrees_with_the_point_extensometers(report):
    data = json.loads((report / "results.json").read_text())
    point, dic = data["measured"], data["measured"]["dic"]
    assert abs(dic["E"] / point["E"] - 1) < E_TOLERANCE
    assert abs(dic["nu"] / point["nu"] - 1) < NU_TOLERANCE
    assert dic["E_difference"] == pytest.approx(dic["E"] / point["E"] - 1)


def test_dic_agrees_with_the_levelled_fe_field_within_its_noise(report):
    """DIC − levelled FE is measurement error: of the order of the static pair's noise floor."""
    d = json.loads((report / "results.json").read_text())["dic"]
    noise, last = d["noise_floor"], d["levelled_last"]
    assert last["u_px"]["rms"] < 3 * noise["sigma_u_px"] + 1e-3
    assert last["v_px"]["rms"] < 3 * noise["sigma_v_px"] + 1e-3
    assert last["exx"]["rms"] < 3 * noise["sigma_exx_microstrain"] * 1e-6 + 1e-5
    assert last["eyy"]["rms"] < 3 * noise["sigma_eyy_microstrain"] * 1e-6 + 1e-5
    assert last["exx"]["points"] > 100
    assert d["converged_last"] > 0.95  # of the subsets in the region of interest
    shift = noise["translation"]  # the target for a rigid sub-pixel translation: |bias| ≤ 0.01 px
    assert abs(shift["bias_u_px"]) < 0.01 and abs(shift["bias_v_px"]) < 0.01 and shift["std_u_px"] < 0.01


def test_the_run_reports_the_dic_challenge_metrics_of_its_camera(report):
    """results.json dic.metrics: the full set, the spatial resolution that of the scene's 21 px
    subset (the affine subset's closed form, ≈ 3.99 h: the issue's "consistent with the subset
    size"), in dic.json and in the report's table."""
    m = json.loads((report / "results.json").read_text())["dic"]["metrics"]
    assert m["level"] == "full"
    sr = m["spatial_resolution"]
    assert sr["displacement_px"] == pytest.approx(sr["theory"]["displacement_px"], rel=0.03)
    assert 3.8 < sr["displacement_px"] / 21 < 4.2
    assert sr["strain_px"] == pytest.approx(sr["theory"]["strain_px"], rel=0.05)
    assert sr["displacement_mm"] == pytest.approx(sr["displacement_px"] * 20.0 / 320)
    assert all(v > 0 for v in m["strain_noise_microstrain"].values())
    assert m["mei"]["displacement_px2"] == pytest.approx(m["noise_floor_px"]["v"] * sr["displacement_px"])
    assert m["mei"]["strain_px2"] == pytest.approx(m["strain_noise_microstrain"]["exy"] * 1e-6 * sr["strain_px"] ** 2)
    assert m["time_s"]["spatial_resolution"] > 0
    assert json.loads((report / "dic" / "dic.json").read_text())["metrics"] == m
    page = (report / "index.html").read_text()
    assert "Strain spatial resolution" in page and "MEI" in page


def test_the_dic_folder_holds_images_fields_levels_and_json(report):
    from vlab.dic.images import read_grey
    from vlab.dic.output import COLUMNS

    dic = report / "dic"
    meta = json.loads((dic / "dic.json").read_text())
    with open(dic / "levels.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["image", "displacement", "force"]
    stems = [r[0] for r in rows[1:]]
    assert stems == sorted(p.stem for p in (dic / "fields").glob("*.csv")) and len(stems) >= 5
    assert sorted(p.stem for p in (dic / "images").glob("*.png")) == [meta["reference"]] + stems
    displacement = [float(r[1]) for r in rows[1:]]
    force = [float(r[2]) for r in rows[1:]]
    assert all(b > a for a, b in zip(displacement, displacement[1:])) and all(f > 0 for f in force)
    with open(dic / "fields" / f"{stems[-1]}.csv", newline="") as fh:
        assert tuple(next(csv.reader(fh))) == COLUMNS
    image = read_grey(dic / "images" / f"{stems[-1]}.png")
    assert image.shape == (128, 320) and image.max() > 255  # 16-bit
    camera = meta["camera"]
    assert camera["pixels"] == [320, 128] and camera["mm_per_px"] == pytest.approx(20.0 / 320)
    assert camera["face"]["axis"] == "z" and camera["face"]["side"] == 1 and "convention" in camera
    assert (dic / "maps.png").stat().st_size > 10_000
    assert "Digital image correlation" in (report / "index.html").read_text()
    source = meta["source"]  # what made the images: the scene's [material] as given, its moduli, the seeds
    assert source["scene"] == "dogbone-dic" and source["material"] == {"model": "linear", "E": 200.0, "nu": 0.3}
    moduli = source["moduli"]  # the closed forms of E and nu, not vlab's conversion
    assert moduli["mu"] == pytest.approx(200.0 / 2.6, rel=1e-14) and moduli["K"] == pytest.approx(200.0 / 1.2, rel=1e-14)
    assert moduli["lambda"] == pytest.approx(200.0 * 0.3 / (1.3 * 0.4), rel=1e-14)
    assert source["seeds"] == {"camera": 0, "speckle": 1}


def test_an_order_2_run_renders_through_quadratic_face_cells(tmp_path):
    """The same scene (the test's small camera) on an order-2 space (27-node hexahedra): the camera
    sees the face through 9-node cells carrying every node's displacement, the DIC virtual
    extensometer still agrees with the point extensometers, and the levelled FE (the same
    quadratic interpolation) agrees with the DIC within its noise."""
    from vlab.api import Scene
    from vlab.report.results import result_to_dict
    from vlab.run import run_scene

    scene = Scene.from_file(_small_camera_scene(tmp_path)).with_values({"mesh.order": 2})
    result = run_scene(scene.parsed)
    face = result.dic.record.view.face
    assert face.cells.shape[1] == 9 and face.nodes.max() >= result.specimen.mesh.nvertices
    data = result_to_dict(result)
    point, dic = data["measured"], data["measured"]["dic"]
    assert abs(dic["E"] / point["E"] - 1) < E_TOLERANCE
    assert abs(dic["nu"] / point["nu"] - 1) < NU_TOLERANCE
    noise, last = data["dic"]["noise_floor"], data["dic"]["levelled_last"]
    assert last["u_px"]["rms"] < 3 * noise["sigma_u_px"] + 1e-3
    assert last["exx"]["rms"] < 3 * noise["sigma_exx_microstrain"] * 1e-6 + 1e-5


def test_the_pixel_to_face_convention_is_the_renderers():
    """View.face_mm (what dic.json states) gives the pixel centres the camera renders (its
    sub-sample grid at supersample 1), and mesh_points puts them on the face's plane."""
    import numpy as np
    import skfem

    from vlab.dic.instrument import build_view
    from vlab.scene.instruments import DicSpec

    mesh = skfem.MeshHex.init_tensor(np.linspace(0, 20, 11), np.linspace(-4, 4, 5), np.linspace(0, 2, 2))
    # the centre is in face coordinates: the bottom face, seen from −z, has x₁ = −x
    for face, (axis, side), centre in (("top", (2, 1), (9.0, 0.5)), ("bottom", (2, -1), (-9.0, 0.5))):
        spec = DicSpec(face, axis, side, {"pixels": (64, 32), "mm_per_px": 0.25, "supersample": 1,
                                          "centre": centre}, {}, {"subset": 11})
        view = build_view(spec, mesh)
        x1, x2 = view.face_mm(np.arange(64), np.arange(32))
        c1, c2 = view.camera.axes(view.face)
        np.testing.assert_allclose(x1, c1, atol=1e-12)
        np.testing.assert_allclose(x2, c2, atol=1e-12)
        P = view.mesh_points(np.array([x1[0]]), np.array([x2[0]]))
        (a1, s1), (a2, s2) = view.face.axes
        assert P[axis, 0] == (2.0 if side > 0 else 0.0)
        assert P[a1, 0] == s1 * x1[0] and P[a2, 0] == s2 * x2[0]
