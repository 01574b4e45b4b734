"""Every report type in a real browser: headless Chromium screenshots the page (kept in
reports/test-artefacts/), every image the page shows exists and is not blank, and each render of a
specimen is framed on it (the specimen spans at least 40 % of its panel's width, measured on the
PNG as the share of columns holding a non-background pixel). The interactive 3-D view loads without
a console error and draws a canvas that is not blank."""

import html
import json
import re
import shutil
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from scenes import scene_dict

BROWSER = next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)
pytestmark = pytest.mark.skipif(BROWSER is None, reason="no chromium on PATH (Debian package 'chromium')")
ROOT = Path(__file__).resolve().parents[1]
ARTEFACTS = ROOT / "reports" / "test-artefacts"
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--enable-unsafe-swiftshader", "--virtual-time-budget=8000"]
STD_FLOOR = 20.0  # grey-level spread of a blank (uniform) picture: 0
MIN_WIDTH_SHARE = 0.40


def browse(page: Path, profile: Path, *args: str, size=(1300, 2600)) -> subprocess.CompletedProcess:
    return subprocess.run([BROWSER, *FLAGS, f"--window-size={size[0]},{size[1]}", f"--user-data-dir={profile}",
                           *args, page.resolve().as_uri()], capture_output=True, text=True, timeout=120)


def screenshot(page: Path, name: str, tmp_path: Path, size=(1300, 2600)) -> np.ndarray:
    png = tmp_path / f"{name}.png"
    proc = browse(page, tmp_path / f"profile-{name}", f"--screenshot={png}", size=size)
    assert png.is_file(), proc.stderr[-2000:]
    ARTEFACTS.mkdir(parents=True, exist_ok=True)
    shutil.copy(png, ARTEFACTS / f"{name}.png")
    return np.asarray(Image.open(png).convert("RGB"), dtype=float)


def page_images(folder: Path) -> list[Path]:
    text = (folder / "index.html").read_text(encoding="utf-8")
    return [folder / html.unescape(src) for src in re.findall(r'<img src=["\']([^"\']+)["\']', text)]


def assert_images_shown(folder: Path) -> list[Path]:
    images = page_images(folder)
    assert images, "the page shows images"
    for image in images:
        assert image.is_file(), image
        assert np.asarray(Image.open(image).convert("L"), dtype=float).std() > STD_FLOOR, f"{image.name} is blank"
    return images


def width_share(pixels: np.ndarray) -> float:
    """Share of columns with a non-background (non-white) pixel."""
    return float(np.mean((pixels[..., :3] < 245).any(axis=-1).any(axis=0)))


def assert_framed(folder: Path, meta: dict) -> None:
    image = np.asarray(Image.open(folder / meta["file"]).convert("RGB"))
    for model, (x0, y0, x1, y1) in zip(meta["models"], meta["panels"]):
        share = width_share(image[y0:y1, x0:x1])
        assert share >= MIN_WIDTH_SHARE, f"{model}: the specimen spans {share:.0%} of its panel"


def test_run_report_in_the_browser(tmp_path):
    from vlab.report.writer import write_run
    from vlab.run import run_scene
    from vlab.scene import apply_overrides, parse_scene

    path = ROOT / "specimens" / "dogbone-iso527-2-1a.toml"
    raw = apply_overrides(tomllib.loads(path.read_text(encoding="utf-8")), {"mesh.size": 6.0, "test.steps": 3})
    scene = parse_scene(raw, origin=path.name, base_dir=path.parent)
    folder = tmp_path / "run"
    write_run(run_scene(scene), folder, path.read_text(encoding="utf-8"))
    shot = screenshot(folder / "index.html", "run-report", tmp_path)
    assert shot.std() > STD_FLOOR
    assert_images_shown(folder)
    assert_framed(folder, json.loads((folder / "comparison.json").read_text())["renders"]["side_by_side"])
    check_interactive_view(folder, tmp_path, "run-view3d")


def test_compare_report_in_the_browser(comparison, tmp_path):
    shot = screenshot(comparison.folder / "index.html", "compare-report", tmp_path)
    assert shot.std() > STD_FLOOR
    assert_images_shown(comparison.folder)
    assert_framed(comparison.folder, comparison.summary["renders"]["side_by_side"])
    check_interactive_view(comparison.folder, tmp_path, "compare-view3d")


def test_a_moved_report_draws_with_its_assets_folder_and_says_why_without(comparison, tmp_path):
    """The reports of a folder share ``_assets/plotly-<version>.min.js``: moved together with it a
    report's 3-D view draws offline; moved alone it says where it expected plotly.js (no blank view)."""
    assets = comparison.folder.parent / "_assets"
    assert assets.is_dir() and not list(comparison.folder.glob("*.js"))
    together = tmp_path / "sent" / comparison.folder.name
    shutil.copytree(comparison.folder, together)
    shutil.copytree(assets, together.parent / "_assets")
    check_interactive_view(together, tmp_path, "moved-view3d")
    alone = tmp_path / "alone" / comparison.folder.name
    shutil.copytree(comparison.folder, alone)
    proc = browse(alone / "view3d.html", tmp_path / "profile-alone", "--dump-dom", size=(1200, 800))
    assert "plotly.js did not load from ../_assets/plotly-" in html.unescape(proc.stdout), proc.stdout[-2000:]


def test_sweep_report_in_the_browser(tmp_path):
    from vlab.study.grid import expand_grid, parse_axis
    from vlab.study.summary import RunKnobs, summarize
    from vlab.study.table import write_sweep_report

    points = expand_grid(scene_dict(name="shot-sweep"), [parse_axis("material.nu=0.3,0.45")])
    summaries = [summarize(p.source, RunKnobs(), p.label) for p in points]
    index = write_sweep_report(tmp_path / "sweep", "shot-sweep: sweep", summaries, {})
    shot = screenshot(index, "sweep-report", tmp_path, size=(1300, 1400))
    assert shot.std() > STD_FLOOR  # the chart and the table, not an empty page
    assert "0.45" in index.read_text(encoding="utf-8")
    assert [p.name for p in assert_images_shown(index.parent)] == ["sweep.png"]


def test_cost_report_in_the_browser(tmp_path):
    from vlab.scene import parse_scene
    from vlab.study.cost import CostOptions, analyse, knob_points
    from vlab.study.cost_report import write_cost_report
    from vlab.study.summary import RunKnobs, summarize

    scene = parse_scene(scene_dict(name="shot-cost"))
    options = CostOptions(levels=3, ratio=2.0, orders=(1,), cells=("hex",))
    summaries = [summarize(p.source, RunKnobs(), p.label) for p in knob_points(scene, options)]
    index = write_cost_report(tmp_path / "cost", "shot-cost", summaries, analyse(scene, summaries, options),
                              0.01, {})
    shot = screenshot(index, "cost-report", tmp_path)
    assert shot.std() > STD_FLOOR
    assert_images_shown(index.parent)


def test_stability_report_in_the_browser(stability_fast_report, tmp_path):
    _, folder = stability_fast_report
    shot = screenshot(folder / "index.html", "stability-report", tmp_path)
    assert shot.std() > STD_FLOOR
    for image in assert_images_shown(folder):
        pixels = np.asarray(Image.open(image).convert("RGB"))
        middle = pixels[int(0.3 * len(pixels)):int(0.9 * len(pixels))]  # below the label in the top-left corner
        assert width_share(middle) >= MIN_WIDTH_SHARE, f"{image.name}: {width_share(middle):.0%}"


ERROR_HOOK = """<script>window.__vlabErrors = [];
window.addEventListener("error", e => window.__vlabErrors.push("error: " + e.message));
window.addEventListener("unhandledrejection", e => window.__vlabErrors.push("rejection: " + e.reason));
const __err = console.error; console.error = (...a) => { window.__vlabErrors.push("console.error: " + a.join(" ")); __err(...a); };
window.addEventListener("load", () => setTimeout(() => { const p = document.createElement("pre");
  p.id = "vlab-errors"; p.textContent = JSON.stringify({errors: window.__vlabErrors,
  canvases: document.querySelectorAll("#view canvas").length,
  images: [...document.images].map(i => [i.getAttribute("src"), i.naturalWidth])}); document.body.appendChild(p); }, 3000));
</script>"""


def page_errors(page: Path, tmp_path: Path, name: str) -> dict:
    """What a copy of ``page`` with the error hook recorded in Chromium: uncaught errors,
    rejections and console.error, the view's canvases, each image's natural width (0: not loaded)."""
    probe = page.with_name(page.stem + "-probe.html")
    probe.write_text(page.read_text(encoding="utf-8").replace("<head>", "<head>" + ERROR_HOOK, 1), encoding="utf-8")
    proc = browse(probe, tmp_path / f"profile-{name}-dom", "--dump-dom", size=(1200, 800))
    probe.unlink()
    found = re.search(r'<pre id="vlab-errors">(.*?)</pre>', proc.stdout, re.S)
    assert found, proc.stderr[-2000:]
    return json.loads(html.unescape(found.group(1)))


FIT = """name = "shot-fit"
[model]
name = "ogden"
terms = 2
incompressible = true
[[data]]
file = "{root}/uniaxial.csv"
kind = "uniaxial"
columns = {{ stretch = "stretch", stress = "nominal_stress_MPa" }}
[[data]]
file = "{root}/equibiaxial.csv"
kind = "equibiaxial"
columns = {{ stretch = "stretch", stress = "nominal_stress_MPa" }}
[[data]]
file = "{root}/pure_shear.csv"
kind = "planar"
columns = {{ stretch = "stretch", stress = "nominal_stress_MPa" }}
role = "validate"
[options]
starts = 4
"""


def test_fit_report_in_the_browser(tmp_path):
    """`vlab fit` as a user runs it (Treloar's data, one mode held out): the console shows no markup
    tags, the page loads without a console error, both figures load and are not blank, and the
    parameter table gives each constant's unit."""
    import sys

    fit = tmp_path / "shot.toml"
    fit.write_text(FIT.format(root=(ROOT / "specimens" / "treloar1944").as_posix()), encoding="utf-8")
    folder = tmp_path / "fit"
    proc = subprocess.run([sys.executable, "-m", "vlab", "fit", str(fit), "--out", str(folder)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr[-2000:]
    printed = proc.stdout + proc.stderr
    assert "shot-fit: ogden (converged)" in printed and "[bold]" not in printed and "[/" not in printed
    report = page_errors(folder / "index.html", tmp_path, "fit")
    assert report["errors"] == [], report
    assert sorted(src for src, _ in report["images"]) == ["curves.png", "stability_map.png"]
    assert all(width > 0 for _, width in report["images"]), report["images"]  # every figure loaded
    shot = screenshot(folder / "index.html", "fit-report", tmp_path)
    assert shot.std() > STD_FLOOR
    assert_images_shown(folder)
    page = (folder / "index.html").read_text(encoding="utf-8")
    assert re.search(r"<td>mu\[0\]</td>(<td>[^<]*</td>){3}<td>MPa</td>", page)
    assert re.search(r"<td>alpha\[0\]</td>(<td>[^<]*</td>){3}<td>1</td>", page)


def check_interactive_view(folder: Path, tmp_path: Path, name: str) -> None:
    """view3d.html loads with no error (an error hook injected into a copy records uncaught errors,
    rejections and console.error; Chromium's --dump-dom reads them back), draws WebGL canvases,
    and its screenshot shows the specimen (pixel spread, colour)."""
    page = folder / "view3d.html"
    text = page.read_text(encoding="utf-8")
    src = html.unescape(re.search(r'<script src="([^"]+)"></script>', text).group(1))  # shared: ../_assets/
    assert page.is_file() and (folder / src).is_file(), src
    assert "https://" not in text.replace(f'<script src="{src}"></script>', "").split("<script id=\"vlab-data\"")[0]
    report = page_errors(page, tmp_path, name)
    assert report["errors"] == [] and report["canvases"] >= 1, report
    shot = screenshot(page, name, tmp_path, size=(1200, 800))
    plot = shot[60:, :]  # below the menus
    assert plot.std() > STD_FLOOR
    hsv = np.asarray(Image.fromarray(plot.astype(np.uint8)).convert("HSV"), dtype=float)
    assert np.mean((hsv[..., 1] > 90) & (hsv[..., 2] > 60)) > 0.01  # the coloured specimen is drawn


def test_budget_report_in_the_browser(tmp_path):
    """`vlab budget`'s page with alignment in both planes and grip slip (a clamped 40 × 10 × 2 bar,
    six samples): the histogram and the three tornado charts load in Chromium and are not blank,
    and the percent-bending table gives the nominal run's B and the samples' mean, u and largest."""
    from types import SimpleNamespace

    from vlab.cli_io import report_destination
    from vlab.scene import parse_scene
    from vlab.study.summary import RunKnobs, summarize
    from vlab.uncertainty.budget import compute_budget
    from vlab.uncertainty.report import write_budget
    from vlab.uncertainty.spec import parse_uncertainty

    src = {"name": "shot-budget", "specimen": {"shape": "block", "size": [40.0, 10.0, 2.0]},
           "mesh": {"size": 2.0, "cell": "hex"}, "material": {"model": "linear", "E": 1000.0, "nu": 0.3},
           "test": {"kind": "uniaxial", "grips": "clamped", "stretch": 1.003, "steps": 2},
           "uncertainty": {"samples": 6, "alignment": {"tilt": [0.1, 0.1]}, "grip_slip": 2e-4,
                           "extensometer_class": "none", "resolution": False}}
    scene = parse_scene(src)
    spec = parse_uncertainty(src["uncertainty"], scene)

    def runner(points, what):
        s = [summarize(p.source, RunKnobs(), p.label, p.base_dir) | {"cache_hit": False} for p in points]
        return SimpleNamespace(summaries=s, cache_hits=0, computed=len(s), seconds={})

    budget, runs = compute_budget(src, spec, tmp_path, runner, scene.measure.modulus_window[0])
    index = write_budget(report_destination(tmp_path / "budget", False), {"scene": "shot-budget"} | budget, spec,
                         runs, "")
    report = page_errors(index, tmp_path, "budget")
    assert report["errors"] == [], report
    assert sorted(src for src, _ in report["images"]) == ["histogram.png", "tornado_E.png", "tornado_E_crosshead.png",
                                                          "tornado_nu.png"]
    assert all(width > 0 for _, width in report["images"]), report["images"]  # every figure loaded
    shot = screenshot(index, "budget-report", tmp_path)
    assert shot.std() > STD_FLOOR
    assert_images_shown(index.parent)
    text = index.read_text(encoding="utf-8")
    pb = budget["percent_bending"]
    assert "ASTM E1012 percent bending" in text and f"{pb['max_abs']:.4g}" in text and f"{pb['u']:.4g}" in text


def test_design_report_in_the_browser(tmp_path):
    """`vlab design` on Treloar's uniaxial data with a Mooney–Rivlin card: the page loads without a
    console error, shows its candidate table and the answer it printed, and is not blank."""
    import sys

    fit = tmp_path / "design.toml"
    fit.write_text(f'name = "shot-design"\n[model]\nname = "mooney-rivlin"\nincompressible = true\n[[data]]\n'
                   f'file = "{(ROOT / "specimens" / "treloar1944" / "uniaxial.csv").as_posix()}"\nkind = "uniaxial"\n'
                   'columns = { stretch = "stretch", stress = "nominal_stress_MPa" }\n[options]\nstarts = 2\n',
                   encoding="utf-8")
    folder = tmp_path / "design"
    proc = subprocess.run([sys.executable, "-m", "vlab", "design", str(fit), "--out", str(folder),
                           "--candidates", "uniaxial,equibiaxial,planar", "--points", "10"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr[-2000:]
    d = json.loads((folder / "design.json").read_text(encoding="utf-8"))
    report = page_errors(folder / "index.html", tmp_path, "design")
    assert report["errors"] == [], report
    shot = screenshot(folder / "index.html", "design-report", tmp_path)
    assert shot.std() > STD_FLOOR
    page = (folder / "index.html").read_text(encoding="utf-8")
    assert html.escape(d["answer"]) in page and f"next: {d['answer']}" in proc.stdout
    assert page.count("<tr") >= len(d["candidates"])  # a row per candidate


def test_dic_report_in_the_browser(tmp_path):
    """`vlab dic` on a rendered speckle pair under a homogeneous strain: the page loads without a
    console error and its strain map loads and is not blank."""
    from typer.testing import CliRunner

    from vlab.cli import app
    from vlab.dic import speckle
    from vlab.dic.images import write_grey

    shape = (128, 144)
    pattern = speckle.make_pattern(shape, size=4.0, density=0.5, seed=5)
    write_grey(tmp_path / "ref.tif", speckle.render(pattern, shape, supersample=2), 16)
    write_grey(tmp_path / "def.tif", speckle.render(pattern, shape, speckle.homogeneous(4e-3, 0.0, (70, 60)),
                                                    supersample=2), 16)
    folder = tmp_path / "dic"
    res = CliRunner().invoke(app, ["dic", str(tmp_path / "ref.tif"), str(tmp_path / "def.tif"), "--out", str(folder),
                                   "--quiet"])
    assert res.exit_code == 0, res.output
    report = page_errors(folder / "index.html", tmp_path, "dic")
    assert report["errors"] == [], report
    assert [src for src, _ in report["images"]] == ["maps/def.png"] and report["images"][0][1] > 0
    shot = screenshot(folder / "index.html", "dic-report", tmp_path)
    assert shot.std() > STD_FLOOR
    assert_images_shown(folder)
