"""The plots a lab looks at first: force against crosshead displacement beside stress–strain, and
loops coloured by cycle with the cycle number in the legend (figures read back from what the
plotting functions drew: vlab.report.figures.describe)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from matplotlib.colors import to_hex
from typer.testing import CliRunner

from helpers_scenes import block_toml
from vlab.cli import app
from vlab.report.comparison_plots import crosshead_displacement, plot_overlay
from vlab.report.effect_plots import _hysteresis, cycle_starts


def _run(tmp_path, name: str, extra: str = "", cyclic: bool = False, **kw) -> dict:
    scene = tmp_path / f"{name}.toml"
    text = block_toml(name, **kw)
    if cyclic:  # the amplitudes give the peak stretch
        text = text.replace(f"stretch = {kw['stretch']:g}\n", "")
    scene.write_text(text + extra)
    res = CliRunner().invoke(app, ["run", str(scene), "--no-render", "--no-estimate", "-q", "-o", str(tmp_path / name)])
    assert res.exit_code == 0, res.output
    return json.loads((tmp_path / name / "results.json").read_text())


@pytest.fixture(scope="module")
def monotonic(tmp_path_factory):
    return _run(tmp_path_factory.mktemp("mono"), "mono", material='model = "neo-hookean"\nE = 10.0\nnu = 0.3',
                stretch=1.5, steps=4)


@pytest.fixture(scope="module")
def cyclic(tmp_path_factory):
    """The Mullins block of specimens/block-mullins-cyclic.toml on one element, 4 levels per ramp."""
    return _run(tmp_path_factory.mktemp("cyc"), "cyc", material='model = "neo-hookean"\nE = 5.0\nnu = 0.45',
                stretch=2.5, steps=4, cyclic=True,
                extra='protocol = "cyclic"\namplitudes = [1.5, 2.0, 2.5]\n[effects.mullins]\nr = 2.0\nm = 0.3\n')


def test_crosshead_displacement_is_grip_strain_times_the_grip_separation(monotonic):
    assert monotonic["specimen"]["grip_separation"] == {"x": 10.0}  # the 10 mm cube between roller grips
    delta = crosshead_displacement(monotonic)
    assert delta[0] == 0.0 and delta[-1] == pytest.approx((1.5 - 1.0) * 10.0, rel=1e-12)
    assert np.all(np.diff(delta) > 0)


def test_run_figure_has_stress_strain_and_force_crosshead_panels(monotonic, tmp_path):
    panels = plot_overlay([monotonic], tmp_path / "s.png")
    assert len(panels) == 2 and (tmp_path / "s.png").stat().st_size > 10_000
    left, right = panels
    assert "stress" in left["ylabel"] and "extensometer strain" in left["xlabel"]
    assert right["xlabel"].startswith("crosshead (grip) displacement") and right["xlabel"].endswith("[mm]")
    assert right["ylabel"] == "load-cell force F [N]" and right["lines"] == 1
    assert right["legend"][0] == "neo-hookean (FE)"  # the models' legend sits beside the right panel
    without = dict(monotonic, specimen=None)  # a results.json of older vlab: no grip separation, one panel
    assert len(plot_overlay([without], tmp_path / "t.png")) == 1


def test_cycle_starts_of_load_unload_cyclic_and_fully_reversed_protocols():
    assert cycle_starts([0, 0.1, 0.2, 0.1, 0.0]) == [0]
    assert cycle_starts([0, 0.5, 0.0, 0.5, 1.0, 0.5, 0.0, 1.5, 0.0]) == [0, 2, 6]
    # a held reading at the turn does not start a cycle of its own
    assert cycle_starts([0, 0.5, 0.0, 0.0, 1.0, 0.0]) == [0, 3]
    # simple shear, 0 → γ₁ → −γ₁ → γ₂ → −γ₂ → 0: two cycles, the return to rest ends the second
    assert cycle_starts([0, 0.1, 0.0, -0.1, 0.0, 0.2, 0.0, -0.2, -0.1, 0.0]) == [0, 3]


def test_cyclic_loops_one_colour_per_cycle_numbered_with_its_peak(cyclic, tmp_path):
    (panel,) = _hysteresis([cyclic], tmp_path / "h.png")
    assert panel["legend"] == ["cycle 1: to 5 mm", "cycle 2: to 10 mm", "cycle 3: to 15 mm"]
    assert panel["lines"] == 3 and panel["xlabel"].endswith("[mm]") and "3 cycles" in panel["title"]
    assert len({to_hex(c) for c in panel["colours"]}) == 3


def test_load_unload_is_one_cycle(tmp_path):
    d = _run(tmp_path, "lu", material='model = "neo-hookean"\nE = 10.0\nnu = 0.3', stretch=1.2, steps=3,
             extra='protocol = "load-unload"\n')
    (panel,) = _hysteresis([d], tmp_path / "h.png")
    assert panel["legend"] == ["cycle 1: to 2 mm"] and panel["lines"] == 1
