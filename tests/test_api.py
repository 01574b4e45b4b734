"""The Python API: its docstring examples and the python blocks of the README and the docs' API page
run as written."""

import doctest
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import vlab
import vlab.api

ROOT = Path(__file__).resolve().parents[1]


def test_the_api_docstring_examples_run(monkeypatch):
    monkeypatch.chdir(ROOT)  # the examples name specimens/… like the README
    outcome = doctest.testmod(vlab.api, optionflags=doctest.ELLIPSIS)
    assert outcome.attempted > 10 and outcome.failed == 0


#: the pages whose python blocks are examples a reader runs as written
EXAMPLE_PAGES = ("README.md", "docs/reference/python-api.md")


@pytest.mark.parametrize("page", EXAMPLE_PAGES)
def test_the_python_blocks_of_the_readme_and_the_api_page_run(page, tmp_path):
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / page).read_text(encoding="utf-8"), re.S)
    assert blocks, f"{page} has python examples"
    (tmp_path / "specimens").symlink_to(ROOT / "specimens")
    for i, block in enumerate(blocks):  # each block a script a reader runs as written
        script = tmp_path / f"example_{i}.py"
        script.write_text(block, encoding="utf-8")
        # a fresh interpreter, as a reader's script runs (and the renders' threads stay out of the
        # test process, whose forked comparison workers would inherit them); reports/ lands in tmp_path
        proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True,
                              timeout=900)  # the commands' examples: a fit, a cost study
        assert proc.returncode == 0, f"{page}, python block {i + 1}: {proc.stderr[-3000:]}"
    assert (tmp_path / "reports" / "api-dogbone" / "index.html").is_file()


@pytest.fixture(scope="module")
def block_result():
    return vlab.Scene.from_dict({
        "name": "api-test", "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
        "mesh": {"size": 5.0, "cell": "hex"}, "material": {"model": "linear", "E": 10.0, "nu": 0.3},
        "test": {"kind": "uniaxial", "grips": "roller", "stretch": 1.01, "steps": 2}}).run()


def test_curve_columns_are_numpy_arrays_by_name(block_result):
    curve = block_result.curve
    for name in ("strain", "stress", "force", "transverse_strain"):
        assert isinstance(curve[name], np.ndarray) and len(curve[name]) == len(curve["strain"])
    assert curve["stress"][-1] == pytest.approx(10.0 * curve["strain"][-1], rel=1e-6)  # linear, roller
    with pytest.raises(KeyError, match="no curve column 'stres'.*strain"):
        curve["stres"]
    with pytest.raises(AttributeError, match="no y axis"):
        curve.y


def test_a_result_shows_as_a_table_in_jupyter(block_result):
    page = block_result._repr_html_()
    assert "<table>" in page and "E measured / input" in page and "completed" in page


def test_a_bad_scene_names_the_field():
    with pytest.raises(vlab.SceneError, match="material.nu"):
        vlab.Scene.from_dict({"name": "bad", "specimen": {"shape": "block", "size": [1.0, 1.0, 1.0]},
                              "mesh": {"size": 1.0}, "material": {"model": "linear", "E": 1.0, "nu": 0.5},
                              "test": {"kind": "uniaxial", "stretch": 1.1}})


def test_a_simple_shear_result_has_its_own_columns_and_shows():
    result = vlab.Scene.from_file(ROOT / "specimens" / "shear-plates-neo-hookean.toml").with_values(
        {"mesh.size": 2.0, "test.steps": 2}).run()
    curve = result.curve
    assert {"shear", "shear_stress", "normal_force"} <= set(curve)
    assert curve.levels == len(curve["shear"]) > 0
    assert "E, nu not measured" in repr(result) and f"{curve.levels} levels" in repr(result)
