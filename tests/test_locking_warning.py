"""The volumetric-locking warning is given where a displacement-only mesh can lock (a non-uniform
field of a near-incompressible solid: clamped grips, shear plates, an imperfection, self-weight),
never on a test whose deformation every mesh represents exactly (the roller rubber blocks)."""

from pathlib import Path

import pytest

from vlab.run import _warnings
from vlab.scene import apply_overrides, load_scene, parse_scene

SPECIMENS = Path(__file__).resolve().parents[1] / "specimens"


def _locking(scene) -> bool:
    return any("volumetric locking" in w for w in _warnings(scene))


@pytest.mark.parametrize("name", ["block-ogden", "block-mooney-rivlin", "block-yeoh", "block-gent",
                                  "block-arruda-boyce", "block-rubber-compare"])
def test_a_roller_rubber_block_is_uniform_and_gets_no_locking_warning(name):
    scene = load_scene(SPECIMENS / f"{name}.toml")
    assert scene.material.moduli.nu > 0.45 and scene.mesh.formulation == "displacement"
    assert not _locking(scene)


@pytest.mark.parametrize("over", [{"test.grips": "clamped"}, {"test.imperfection": 0.01, "test.stretch": 0.8}])
def test_a_non_uniform_field_of_the_same_block_keeps_the_warning(over):
    scene = load_scene(SPECIMENS / "block-ogden.toml")
    changed = parse_scene(apply_overrides(scene.source, over), base_dir=scene.base_dir)
    assert _locking(changed)


def test_near_incompressible_shear_plates_are_warned():
    scene = load_scene(SPECIMENS / "shear-plates-neo-hookean.toml")
    changed = parse_scene(apply_overrides(scene.source, {"material.nu": 0.499}), base_dir=scene.base_dir)
    assert _locking(changed) and "mixed" in " ".join(_warnings(changed))


def run_cli_quietly(tmp_path, replacements: dict):
    """`vlab run --quiet` of the Gent block (one element, two steps to stretch 1.2) with the
    file's text changed by ``replacements``: what the user sees on stderr."""
    import os
    import subprocess
    import sys

    text = (SPECIMENS / "block-gent.toml").read_text(encoding="utf-8")
    for old, new in {"size = 2.5": "size = 10.0", "steps = 12": "steps = 2", "stretch = 3.2": "stretch = 1.2",
                     **replacements}.items():
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "gent.toml"
    path.write_text(text, encoding="utf-8")
    return subprocess.run([sys.executable, "-m", "vlab", "run", str(path), "--quiet", "--no-render", "--no-estimate",
                           "-o", str(tmp_path / "r")], capture_output=True, text=True, timeout=300,
                          env=os.environ | {"PYTHONPATH": str(SPECIMENS.parent)}, cwd=tmp_path)


def test_a_roller_rubber_block_run_prints_no_warning(tmp_path):
    proc = run_cli_quietly(tmp_path, {})
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr


def test_the_same_block_clamped_prints_the_locking_warning(tmp_path):
    proc = run_cli_quietly(tmp_path, {'grips = "roller"': 'grips = "clamped"'})
    assert proc.returncode == 0, proc.stderr
    said = " ".join(proc.stderr.split())  # the console wraps long lines
    assert "expect volumetric locking" in said and 'mesh.formulation = "mixed"' in said, proc.stderr
