"""What the gallery's scripts share: a specimen file run on a coarse mesh (as the test suite runs
every file: tests/test_specimen_files.py), its report written to a scratch folder, and the
report's render and curve shown in one matplotlib figure (which the gallery keeps); the other
examples' report figures (a fit's, a cost study's) shown the same way (:func:`show_images`)."""

from __future__ import annotations

import tempfile
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SPECIMENS = ROOT / "specimens"
SCRATCH = Path(tempfile.mkdtemp(prefix="vlab-gallery-"))

# the report's main plot of each test kind and protocol (vlab/report/kind_plots.py names them)
CURVES = ("hysteresis.png", "relaxation.png", "creep.png", "stress_strain.png", "shear.png",
          "biaxial.png", "planar.png")


def coarse_values(path: Path) -> dict:
    """The gallery's budget (vlab.scene.coarse, the test suite's too): at most four load steps and
    up to twice the file's element size, keeping two elements across the narrowest width (the
    file's own mesh is what `vlab run` uses)."""
    from vlab.scene.coarse import coarse_overrides

    return coarse_overrides(tomllib.loads(path.read_text(encoding="utf-8")), path.parent)


def show_images(paths: list[Path], title: str):
    """The PNGs one above the other, each at the figure's full width, in one matplotlib figure
    (which the gallery keeps; nothing returned, so a script's last line prints no Figure repr)."""
    import matplotlib.pyplot as plt
    from matplotlib.image import imread

    images = [imread(p) for p in paths]
    heights = [image.shape[0] / image.shape[1] for image in images]
    fig, axes = plt.subplots(len(images), 1, figsize=(9.0, 9.0 * sum(heights) + 0.4), squeeze=False,
                             gridspec_kw={"height_ratios": heights})
    for ax, image in zip(axes[:, 0], images):
        ax.imshow(image)
        ax.set_axis_off()
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()


def show(name: str, values: dict | None = None):
    """Run specimens/<name>.toml coarse, write its report, draw its render above its curve;
    returns the vlab.Result. ``values`` (dotted keys) replace the coarse budget's where a curve
    needs more (a pressure maximum, a loop's shape); the caption names every value changed."""
    import vlab

    path = SPECIMENS / f"{name}.toml"
    values = coarse_values(path) | (values or {})
    start = time.perf_counter()
    result = vlab.Scene.from_file(path).with_values(values).run()
    folder = SCRATCH / name
    result.write_report(folder)
    seconds = time.perf_counter() - start
    renders = sorted(folder.glob("render_*.png"))
    curve = next((folder / c for c in CURVES if (folder / c).is_file()), None)
    show_images([p for p in (renders[:1] + [curve]) if p is not None],
                f"{path.name} ({', '.join(f'{k} = {v:g}' for k, v in values.items())})")
    print(f"{name}: run and report in {seconds:.1f} s")
    return result
