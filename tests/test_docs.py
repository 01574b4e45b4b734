"""The documentation's structure: the README stays short and says the commands CI runs, every
docs page has one title and is reached by the site's toctrees, every specimen file is described.
The build itself (warnings as errors) is a step of .ci/run, the command the README gives."""

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
README = (ROOT / "README.md").read_text(encoding="utf-8")
CI = (ROOT / ".ci" / "run").read_text(encoding="utf-8")


def _outside_fences(text: str) -> list[str]:
    lines, fence = [], False
    for line in text.splitlines():
        if line.lstrip().startswith(("```", "~~~")):
            fence = not fence
        elif not fence:
            lines.append(line)
    return lines


def _pages() -> list[Path]:
    return sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts and "gallery" not in p.parts)


def test_the_readme_is_what_a_person_reads_first():
    assert len(README.splitlines()) <= 250
    assert "docs/_static/" in README  # one picture


def test_ci_runs_the_readmes_test_command_and_its_docs_build():
    test = re.search(r"^(python -m pip install -e \"\.\[test\]\" && python -m pytest -q)", README, re.M).group(1)
    docs = re.search(r"^(python -m pip install -e \"\.\[docs\]\" && python -m sphinx [^#\n]*?)\s*(#|$)", README, re.M)
    ci = [line.strip() for line in CI.splitlines()]
    assert test in ci and docs.group(1) in ci
    assert " -W " in docs.group(1)  # warnings are errors


def test_every_docs_page_has_exactly_one_title():
    for page in _pages():
        titles = [line for line in _outside_fences(page.read_text(encoding="utf-8")) if line.startswith("# ")]
        assert len(titles) == 1, f"{page.relative_to(ROOT)}: {len(titles)} top-level titles"


def test_every_docs_page_is_in_a_toctree():
    """The reference pages are listed by name, a section's pages by its own index (the tutorials:
    docs/tutorials/index.md); every other page directly under docs/ is picked up by the Guides
    toctree's glob, so a page another change adds appears without editing index.md."""
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    trees = re.findall(r"```\{toctree\}\n(.*?)```", index, re.S)
    assert any(":glob:" in tree and re.search(r"^\*$", tree, re.M) for tree in trees)
    named = {line.strip() for tree in trees for line in tree.splitlines() if line.strip() and not line.startswith(":")}
    for section in [name for name in named if name.endswith("/index") and (DOCS / f"{name}.md").is_file()]:
        folder = section.rsplit("/", 1)[0]  # a section's own index (docs/tutorials/index.md) lists its pages
        for tree in re.findall(r"```\{toctree\}\n(.*?)```", (DOCS / f"{section}.md").read_text(encoding="utf-8"), re.S):
            named |= {f"{folder}/{line.strip()}" for line in tree.splitlines() if line.strip() and not line.startswith(":")}
    for page in _pages():
        name = page.relative_to(DOCS).with_suffix("").as_posix()
        if name == "index":
            continue
        assert name in named or "/" not in name or f"{name.split('/')[0]}/*" in named, f"{name} is in no toctree"


def test_every_specimen_file_is_described():
    page = (DOCS / "reference" / "specimens.md").read_text(encoding="utf-8")
    for path in sorted((ROOT / "specimens").glob("*.toml")):
        assert f"`{path.name}`" in page, f"{path.name} is not described in docs/reference/specimens.md"


def _gallery_scripts() -> list[Path]:
    """The scripts sphinx-gallery runs: docs/conf.py's filename_pattern in its examples_dirs."""
    conf = (DOCS / "conf.py").read_text(encoding="utf-8")
    pattern = re.search(r'"filename_pattern":\s*r"([^"]+)"', conf).group(1)
    examples = DOCS / re.search(r'"examples_dirs":\s*"([^"]+)"', conf).group(1)
    return [p for p in sorted(examples.glob("*.py")) if re.search(pattern, "/" + p.name)]


def _top_level_calls(script: Path) -> list[ast.Call]:
    """The calls a script makes in its module-level statements (not in a function, a branch or a
    comment: what runs whenever the gallery builds)."""
    tree = ast.parse(script.read_text(encoding="utf-8"), filename=str(script))
    return [node for stmt in tree.body if isinstance(stmt, (ast.Expr, ast.Assign))
            for node in ast.walk(stmt) if isinstance(node, ast.Call)]


def test_every_specimen_file_is_run_by_a_gallery_script():
    """Each specimens/*.toml is shown (gallery_helpers.show('<name>'), which runs it and draws its
    render and curve) by a script the docs build runs, and every name shown is a file there."""
    shown = {}
    for script in _gallery_scripts():
        for call in _top_level_calls(script):
            if isinstance(call.func, ast.Name) and call.func.id == "show" and call.args \
                    and isinstance(call.args[0], ast.Constant) and isinstance(call.args[0].value, str):
                shown.setdefault(call.args[0].value, script.name)
    files = {path.stem for path in (ROOT / "specimens").glob("*.toml")}
    missing = sorted(files - set(shown))
    assert not missing, f"specimen files in no gallery script (add show('<name>') to docs/examples/plot_*.py): {missing}"
    assert not set(shown) - files, f"gallery scripts show files specimens/ does not hold: {sorted(set(shown) - files)}"


def test_the_gallery_runs_the_fitting_examples_and_the_cost_study():
    called = {f"{call.func.value.id}.{call.func.attr}" for script in _gallery_scripts() for call in _top_level_calls(script)
              if isinstance(call.func, ast.Attribute) and isinstance(call.func.value, ast.Name)}
    assert {"vlab.fit", "vlab.export", "vlab.cost"} <= called


def test_the_readmes_relative_links_exist():
    for target in re.findall(r"\]\(((?!https?:)[^)#]+)", README):
        assert (ROOT / target).exists(), target
