"""Random command lines for the CLI fuzz (tests/test_fuzz_cli.py): mutated scene text, random
bytes, random --out paths (existing user folders included), random specimen.file paths, random
cache corruption; and the invariants every outcome must satisfy."""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from hypothesis import strategies as st

SPECIMENS = Path(__file__).parent.parent / "specimens"

BLOCK = """name = "fuzz-block"
[specimen]
shape = "block"
size = [10.0, 8.0, 6.0]
[mesh]
size = 5.0
order = 1
cell = "hex"
[material]
model = "neo-hookean"
E = 10.0
nu = 0.3
[test]
kind = "uniaxial"
grips = "roller"
stretch = 1.2
steps = 2
"""
SHEET = """name = "fuzz-sheet"
[specimen]
shape = "sheet"
size = [20.0, 10.0]
thickness = 1.0
[mesh]
size = 5.0
cell = "quad"
[material]
model = "stvk"
E = 5.0
nu = 0.25
[test]
kind = "biaxial"
grips = "clamped"
stretch = [1.1, 1.05]
steps = 2
"""
BAR = (SPECIMENS / "mesh-import-bar.toml").read_text().replace("steps = 4", "steps = 1")
SEEDS = {"block": BLOCK, "sheet": SHEET, "bar": BAR}

NUMBERS = ["0", "-1", "1e-6", "1e300", "nan", "inf", "-inf", "1", "2", "3", "1.01", "0.9", "0.49999", "25",
           "true", '"x"', "[1, 2]", "[]", "{}", "2.5"]
STRINGS = ['""', '"[/x]"', '"[material]"', '"hex"', '"tet"', '"quad"', '"mooney"', '"roller"', '"biaxial"',
           '"../x.msh"', '"/dev/zero"', '"meshes"', '"meshes/bar.msh"', '"meshes/corrupt.vtu"', "'[bold]'"]
LINES = ["[material]", "[/x]", "[mesh]", "foo = 1", "max_dofs = 10", "max_dofs = 0", 'file = "/dev/zero"',
         "symmetry = \"half\"", "order = 2", "[effects.gravity]", "imperfection = 0.1", "=", "[[x]]",
         "steps = 1000000", "size = 1e-6", "gauge_size = 0.1", "rtol = 1e-14"]
SPECIMEN_FILES = ["meshes/bar.msh", "../outside/bar.msh", "/dev/zero", "meshes", "missing.msh", "meshes/corrupt.vtu",
                  "meshes/notmesh.msh", "mydocs/thesis.txt", "meshes/bar.msh\x00", "[/x].msh"]
OUTS = [None, None, None, "out", "out", "deep/er/out", "mydocs", ".", "scene.toml", "meshes", "r[/x]", "n" * 300, "reports", "deep/er/out",
        "mydocs/thesis.txt", "..", "reports/.cache"]


@st.composite
def mutated(draw, text: str) -> str:
    lines = text.splitlines()
    for _ in range(draw(st.sampled_from([0, 0, 0, 1, 1, 2, 4]))):  # often valid: runs reach the solver
        op = draw(st.sampled_from(["delete", "duplicate", "number", "string", "insert", "char"]))
        i = draw(st.integers(0, max(0, len(lines) - 1)))
        if not lines:
            lines = [draw(st.sampled_from(LINES))]
            continue
        line = lines[i]
        if op == "delete":
            lines.pop(i)
        elif op == "duplicate":
            lines.insert(i, line)
        elif op == "number":
            new = draw(st.sampled_from(NUMBERS))
            lines[i] = re.sub(r"-?\d+(\.\d+)?(e-?\d+)?", new, line, count=1) if re.search(r"\d", line) else line
        elif op == "string":
            lines[i] = re.sub(r'"[^"]*"', draw(st.sampled_from(STRINGS)), line, count=1)
        elif op == "insert":
            lines.insert(i, draw(st.sampled_from(LINES)))
        else:
            j = draw(st.integers(0, max(0, len(line) - 1)))
            lines[i] = line[:j] + draw(st.sampled_from(list("[]=\"'.0x# \t\\"))) + line[j + 1:]
    return "\n".join(lines) + "\n"


@dataclass
class Case:
    text: bytes
    out: str | None
    specimen_file: str | None
    extra: list[str] = field(default_factory=list)


@st.composite
def cases(draw, render: bool = False) -> Case:
    kind = draw(st.sampled_from(["block", "block", "sheet", "bar", "bar", "bytes"]))
    specimen_file = None
    if kind == "bytes":
        text = draw(st.binary(max_size=300))
    else:
        source = SEEDS[kind]
        if kind == "bar" and draw(st.integers(0, 3)) == 0:
            specimen_file = draw(st.sampled_from(SPECIMEN_FILES))
            source = source.replace('"meshes/bar.msh"', json.dumps(specimen_file))
        text = draw(mutated(source)).encode("utf-8")
    extra = [] if render and draw(st.booleans()) else ["--no-render"]
    extra += draw(st.sampled_from([["--no-estimate"], [], ["--force"], ["--no-estimate", "--force"]]))
    return Case(text, draw(st.sampled_from(OUTS)), specimen_file, extra)


def make_lab(root: Path) -> None:
    """A user's working folder: documents, a mesh folder (one corrupt and one non-mesh file), a
    mesh outside it, a stale vlab cache."""
    (root / "mydocs").mkdir()
    (root / "mydocs" / "thesis.txt").write_text("years of work")
    (root / "meshes").mkdir()
    (root / "meshes" / "bar.msh").write_bytes((SPECIMENS / "meshes" / "bar.msh").read_bytes())
    (root / "meshes" / "corrupt.vtu").write_text("<VTKFile type='UnstructuredGrid'><garb")
    (root / "meshes" / "notmesh.msh").write_text("hello\n")
    (root.parent / "outside").mkdir(exist_ok=True)
    (root.parent / "outside" / "bar.msh").write_bytes((SPECIMENS / "meshes" / "bar.msh").read_bytes())
    (root / "reports" / ".cache" / "ab").mkdir(parents=True)
    (root / "reports" / ".cache" / "ab" / "entry.json").write_text("{}")


def snapshot(root: Path) -> dict[str, str]:
    """path -> sha256 of its bytes ("dir" for folders) of every entry under ``root``."""
    out = {}
    for dirpath, dirs, files in os.walk(root):
        for d in dirs:
            out[os.path.relpath(os.path.join(dirpath, d), root)] = "dir"
        for f in files:
            p = os.path.join(dirpath, f)
            try:
                out[os.path.relpath(p, root)] = hashlib.sha256(Path(p).read_bytes()).hexdigest()
            except OSError:
                out[os.path.relpath(p, root)] = "unreadable"
    return out


FIELD = re.compile(r"(specimen|mesh|material|test|measure|solver|effects)\.\w+|\[[\w.]+\]|--\w+|\.toml|"
                   r"\bname\b|description|top-level key|section|TOML|scene file|\.msh|\.vtu")


def inside(path: str, folder: str | None) -> bool:
    return folder is not None and (path == folder or path.startswith(folder.rstrip("/") + "/"))


def report_folder(output: str) -> str | None:
    m = re.search(r"report: (.+)/index\.html", output)
    return m.group(1) if m else None


def finite(value) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, dict):
        return all(finite(v) for v in value.values())
    if isinstance(value, list):
        return all(finite(v) for v in value)
    return True


def check_converged_report(folder: Path) -> None:
    """A results.json that says converged has finite numbers and a complete curve."""
    data = json.loads((folder / "results.json").read_text())
    if not data["converged"]:
        assert data.get("failure"), "a stopped run names its failure"
        return
    assert finite(data["measured"]) and finite(data["curve"]), "non-finite number in a converged report"
    curve = {k: v for k, v in data["curve"].items() if isinstance(v, list)}
    lengths = {len(v) for v in curve.values()}
    assert len(lengths) == 1 and lengths.pop() >= 2, f"curve columns of unequal or no length: {lengths}"
    test = data["scene"]["source"]["test"]
    stretch = test.get("stretch")
    if test.get("protocol", "monotonic") == "monotonic" and stretch is not None:
        want = stretch[0] if isinstance(stretch, list) else stretch
        last = data["curve"]["stretch"][-1]
        assert abs(last - want) <= 1e-9 * max(1.0, abs(want)), f"curve ends at stretch {last}, asked {want}"
