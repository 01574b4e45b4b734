"""What the gallery's scripts share: a specimen file run on a coarse mesh (as the test suite runs
every file: tests/test_specimen_files.py), its report written to a scratch folder, and the
report's render and curve shown side by side in one matplotlib figure (which the gallery keeps)."""

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
    """Up to twice the file's element size, keeping two elements across the narrowest width, and
    at most four load steps: the gallery's budget (the file's own mesh is what `vlab run` uses)."""
    from vlab.scene import parse_scene

    raw = tomllib.loads(path.read_text(encoding="utf-8"))
    spec = parse_scene(raw, base_dir=path.parent).specimen
    values: dict = {"test.steps": min(raw["test"].get("steps", 10), 4)}
    if spec.shape in ("mesh", "cad") or "gauge_size" in raw["mesh"]:
        return values
    narrow = {"dogbone": lambda: spec.dimensions.width, "block": lambda: min(spec.size[1:]),
              "sheet": lambda: spec.size[1], "cruciform": lambda: spec.dimensions.gauge_region / 2,
              "planar-tension": lambda: spec.thickness, "shear": lambda: spec.gap,
              "double-lap": lambda: spec.gap}[spec.shape]()
    size = raw["mesh"]["size"]
    values["mesh.size"] = max(size, min(2 * size, narrow / 2))
    return values


def show(name: str):
    """Run specimens/<name>.toml coarse, write its report, draw its render beside its curve;
    returns the vlab.Result."""
    import matplotlib.pyplot as plt
    from matplotlib.image import imread

    import vlab

    path = SPECIMENS / f"{name}.toml"
    values = coarse_values(path)
    start = time.perf_counter()
    result = vlab.Scene.from_file(path).with_values(values).run()
    folder = SCRATCH / name
    result.write_report(folder)
    seconds = time.perf_counter() - start
    renders = sorted(folder.glob("render_*.png"))
    curve = next((folder / c for c in CURVES if (folder / c).is_file()), None)
    images = [imread(p) for p in (renders[:1] + [curve]) if p is not None]
    heights = [image.shape[0] / image.shape[1] for image in images]  # one column, each at full width
    fig, axes = plt.subplots(len(images), 1, figsize=(9.0, 9.0 * sum(heights) + 0.4), squeeze=False,
                             gridspec_kw={"height_ratios": heights})
    for ax, image in zip(axes[:, 0], images):
        ax.imshow(image)
        ax.set_axis_off()
    fig.suptitle(f"{path.name} ({', '.join(f'{k} = {v:g}' for k, v in values.items())})", fontsize=10)
    fig.tight_layout()
    print(f"{name}: run and report in {seconds:.1f} s")
    return result
