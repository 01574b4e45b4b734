"""The tutorials (docs/tutorials/) run as written: each page's python blocks, in order, as one
script in a fresh interpreter (a reader follows a page top to bottom, so a later block may use
what an earlier one defined), in an empty folder that holds only a link to specimens/; and each
scene a page shows as TOML is one vlab accepts. The blocks check the figures their page quotes,
so a change that moves a number fails here until the page says the new one."""

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

import vlab

ROOT = Path(__file__).resolve().parents[1]
TUTORIALS = sorted(p for p in (ROOT / "docs" / "tutorials").glob("*.md") if p.name != "index.md")


def _blocks(page: Path, language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```", page.read_text(encoding="utf-8"), re.S | re.M)


def test_there_are_five_tutorials_in_their_toctree_before_the_gallery():
    landing = (ROOT / "docs" / "tutorials" / "index.md").read_text(encoding="utf-8")
    learn = re.search(r":caption: Learn\n(.*?)```", (ROOT / "docs" / "index.md").read_text(encoding="utf-8"), re.S)
    assert [line.strip() for line in learn.group(1).splitlines() if line.strip()] == ["tutorials/index", "gallery/index"]
    tree = re.search(r"```\{toctree\}\n(.*?)```", landing, re.S).group(1).split()
    assert len(TUTORIALS) == 5
    for page in TUTORIALS:
        assert page.stem in tree, f"{page.name} is not in the toctree of docs/tutorials/index.md"
        assert f"{{doc}}`{page.stem}`" in landing, f"{page.name} is not linked from docs/tutorials/index.md"


@pytest.mark.parametrize("page", TUTORIALS, ids=lambda p: p.stem)
def test_the_python_blocks_of_a_tutorial_run(page, tmp_path):
    blocks = _blocks(page, "python")
    assert blocks, f"{page.name} has no python block"
    (tmp_path / "specimens").symlink_to(ROOT / "specimens")
    script = tmp_path / f"{page.stem}.py"
    script.write_text("\n".join(blocks), encoding="utf-8")
    env = {**__import__("os").environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True,
                          timeout=600, env=env)
    assert proc.returncode == 0, f"{page.name}: {proc.stderr[-3000:]}"


@pytest.mark.parametrize("page", TUTORIALS, ids=lambda p: p.stem)
def test_the_scenes_a_tutorial_shows_are_valid(page):
    for block in _blocks(page, "toml"):
        raw = tomllib.loads(block)
        if "specimen" in raw:  # a scene (a fit file has [[data]] instead)
            vlab.Scene.from_dict(raw, base_dir=ROOT / "specimens")


def _cli():
    import typer.main

    from vlab.cli import app

    return typer.main.get_command(app)


@pytest.mark.parametrize("page", TUTORIALS, ids=lambda p: p.stem)
def test_the_commands_a_tutorial_shows_parse(page):
    """Each `vlab …` line of a page's bash blocks names a command and options the command line has,
    with values of the right type (parsed by the CLI's own parser, not run), and the shipped files
    it names exist."""
    import shlex

    group = _cli()
    lines = [line for block in _blocks(page, "bash") for line in block.splitlines() if line.startswith("vlab ")]
    for line in lines:
        name, *args = shlex.split(line)[1:]
        assert name in group.commands, f"{page.name}: {line!r}: no command {name!r}"
        group.commands[name].make_context(name, list(args))  # a click UsageError names the bad option
        for arg in args:
            assert not arg.startswith("specimens/") or (ROOT / arg).exists(), f"{page.name}: {line!r}: no {arg}"
