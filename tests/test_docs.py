"""The documentation's structure: the README stays short and says the commands CI runs, every
docs page has one title and is reached by the site's toctrees, every specimen file is described.
The build itself (warnings as errors) is a step of .ci/run, the command the README gives."""

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


def test_the_readmes_relative_links_exist():
    for target in re.findall(r"\]\(((?!https?:)[^)#]+)", README):
        assert (ROOT / target).exists(), target
