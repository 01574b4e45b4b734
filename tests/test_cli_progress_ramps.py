"""The progress display of `vlab run` says which ramp the levels belong to: a load–unload test with
steps = 10 runs 19 levels, shown as "loading 10/10, unloading 3/9", not as 13 of 19 anonymous levels."""

import re
from pathlib import Path

from typer.testing import CliRunner

from vlab.cli import app
from vlab.cli_progress import ramp_text, ramps_of

SPECIMENS = Path(__file__).resolve().parents[1] / "specimens"


def test_load_unload_levels_are_split_into_their_ramps():
    t = [k / 10 for k in range(1, 11)] + [1 - k / 9 for k in range(1, 10)]  # 10 up, 9 down: 19 levels
    ramps = ramps_of(t)
    assert ramps == [("loading", 10), ("unloading", 9)]
    assert ramp_text(ramps, 4) == "loading 4/10"
    assert ramp_text(ramps, 13) == "loading 10/10, unloading 3/9"


def test_cycles_and_holds_are_named():
    assert ramps_of([0.5, 1, 0.5, 0, 0.5, 1, 0.5, 0]) == [
        ("cycle 1 loading", 2), ("cycle 1 unloading", 2), ("cycle 2 loading", 2), ("cycle 2 unloading", 2)]
    assert ramps_of([0.5, 1, 1, 1]) == [("loading", 2), ("hold", 2)]
    ramps = ramps_of([0.5, 1, 0.5, 0, 0.5, 1, 0.5, 0])
    assert ramp_text(ramps, 7) == "cycle 2 unloading 1/2"  # both would not fit the column
    assert ramp_text(ramps, 7, width=80) == "cycle 2 loading 2/2, cycle 2 unloading 1/2"


def test_vlab_run_shows_the_ramp_of_a_load_unload_test(tmp_path):
    text = (SPECIMENS / "block-plasticity-load-unload.toml").read_text(encoding="utf-8")
    scene = tmp_path / "lu.toml"
    scene.write_text(text.replace("size = 5.0", "size = 10.0").replace("steps = 20", "steps = 3"), encoding="utf-8")
    result = CliRunner().invoke(app, ["run", str(scene), "--no-render", "--no-estimate", "-o", str(tmp_path / "r")])
    assert result.exit_code == 0, result.output
    found = re.search(r"loading (\d+)/\1, unloading (\d+)/\2 .* (\d+)/(\d+) ", result.stderr)
    assert found, result.stderr
    up, down, done, total = map(int, found.groups())
    assert done == total == up + down, found.group(0)
