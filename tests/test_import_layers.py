"""The package's import graph: no cycle among module-level imports, and no module importing a
layer above its own (read with ast, so nothing is imported to check it).

Layers, bottom to top (a module may import its own layer and any layer below):

    0 foundation   vlab (package), fields, tensor, moduli, jit, settings, data
    1 registries   materials, geometry, loading, effects   (pure specs, laws, shapes, kinds, effects)
    2 scene        the file format; delegates to the registries below it (and the grammar of the
                   [uncertainty] table, vlab.uncertainty.spec and .classes, checked with the scene)
    3 fe           spaces, bodies, assembly, Newton, stepping, linear solvers
    4 checks       run-time admissibility, stability monitor, buckling, imperfection
    5 measure      instruments, recorder, fits; dic (the image-correlation engine: an instrument)
    6 post, render cell fields, snapshots, VTU; off-screen renders
    7 report       results.json, CSV, PNG, HTML
    8 run          the one sequencer, and its stages (vlab.pipeline: prepare, solve, measure)
    9 compare, study, verification, identify, export (solver cards), uncertainty (budgets),
      dic.command (a DIC job's report folder)
   10 cli          (and vlab.cli_io, vlab.__main__, cli_progress: the terminal display; api and api_*: the
                   Python API;
      the command modules that speak the CLI's exit codes: identify.command, identify.design_command,
      uncertainty.command, dic.cli)

The scene sits above the registries (not at the very bottom) because its parts delegate to them:
the shape, kind, model and effect registries own their grammar. Function-level imports (lazy, to
keep start-up light) are listed separately; one that reaches upward must be in ALLOWED_UPWARD with
the reason.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "vlab"

LAYERS = {
    "vlab": 0, "vlab.fields": 0, "vlab.tensor": 0, "vlab.moduli": 0, "vlab.jit": 0, "vlab.settings": 0,
    "vlab.data": 0,
    "vlab.materials": 1, "vlab.geometry": 1, "vlab.loading": 1, "vlab.effects": 1,
    "vlab.scene": 2, "vlab.scenes": 2, "vlab.uncertainty.spec": 2, "vlab.uncertainty.classes": 2,
    "vlab.fe": 3,
    "vlab.checks": 4,
    "vlab.measure": 5, "vlab.dic": 5,
    "vlab.post": 6, "vlab.render": 6,
    "vlab.report": 7,
    "vlab.run": 8, "vlab.pipeline": 8,
    "vlab.compare": 9, "vlab.study": 9, "vlab.verification": 9, "vlab.identify": 9,
    "vlab.export": 9, "vlab.uncertainty": 9, "vlab.dic.command": 9,
    "vlab.identify.command": 10, "vlab.identify.design_command": 10, "vlab.uncertainty.command": 10,
    "vlab.dic.cli": 10,
    "vlab.cli": 10, "vlab.cli_io": 10, "vlab.cli_progress": 10, "vlab.api": 10, "vlab.__main__": 10,
    "vlab.api_tables": 10, "vlab.api_fit": 10, "vlab.api_studies": 10, "vlab.api_compare": 10,
    "vlab.api_checks": 10,
}

# (importing module, imported module): why a function-level import may reach upward.
ALLOWED_UPWARD: dict[tuple[str, str], str] = {
    ("vlab.effects.gravity", "vlab.fe.external_load"):
        "the effect's build hook, called by run only: its grammar is parsed with the scene, which "
        "must not load the solver",
}


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def layer_of(module: str) -> int:
    """The layer of the longest LAYERS prefix of `module`."""
    parts = module.split(".")
    for n in range(len(parts), 0, -1):
        if ".".join(parts[:n]) in LAYERS:
            return LAYERS[".".join(parts[:n])]
    raise KeyError(f"{module} is in no layer: add it to LAYERS")


def _targets(node: ast.AST, module: str, is_package: bool) -> list[str]:
    if isinstance(node, ast.Import):
        return [a.name for a in node.names if a.name.startswith("vlab")]
    if not isinstance(node, ast.ImportFrom):
        return []
    if node.level:  # relative import
        base = module.split(".")[: len(module.split(".")) - node.level + (1 if is_package else 0)]
        source = ".".join(base + ([node.module] if node.module else []))
    else:
        source = node.module or ""
    if not source.startswith("vlab"):
        return []
    # `from vlab.x import y` imports vlab.x.y when y is a submodule
    out = []
    for alias in node.names:
        sub = f"{source}.{alias.name}"
        out.append(sub if _exists(sub) else source)
    return out


def _exists(module: str) -> bool:
    path = PACKAGE.parent.joinpath(*module.split("."))
    return path.with_suffix(".py").exists() or (path / "__init__.py").exists()


def imports() -> tuple[dict[str, set[str]], dict[str, set[str]]]:
    """(module-level, function-level) vlab imports of every module."""
    top: dict[str, set[str]] = {}
    lazy: dict[str, set[str]] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        module = module_name(path)
        tree = ast.parse(path.read_text(encoding="utf-8"))
        top[module], lazy[module] = set(), set()
        _walk(tree, module, path.name == "__init__.py", top[module], lazy[module], nested=False)
    return top, lazy


def _walk(node, module, is_package, top, lazy, nested):
    for child in ast.iter_child_nodes(node):
        inner = nested or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        if isinstance(child, ast.If) and _is_type_checking(child.test):
            continue  # annotations only, never executed
        (lazy if nested else top).update(_targets(child, module, is_package))
        _walk(child, module, is_package, top, lazy, inner)


def _is_type_checking(test) -> bool:
    return isinstance(test, ast.Name) and test.id == "TYPE_CHECKING" or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def upward(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    return sorted((m, t) for m, targets in graph.items() for t in targets
                  if layer_of(t) > layer_of(m) and not t.startswith(m + "."))


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v), on.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def _no_package_self_edges(graph):
    """A package's __init__ importing its own submodules is not a cycle with them."""
    return {m: {t for t in ts if not (t.startswith(m + ".") and m in graph)} for m, ts in graph.items()}


def test_every_module_of_the_package_is_in_a_layer():
    top, _ = imports()
    for module in top:
        layer_of(module)


def test_module_level_imports_form_no_cycle():
    top, _ = imports()
    assert cycles(_no_package_self_edges(top)) == []


def test_no_module_level_import_reaches_a_layer_above():
    top, _ = imports()
    assert upward(top) == []


def test_function_level_imports_reach_upward_only_where_the_allow_list_says_why():
    _, lazy = imports()
    found = upward(lazy)
    assert [edge for edge in found if edge not in ALLOWED_UPWARD] == []
    assert [edge for edge in ALLOWED_UPWARD if edge not in found] == [], "stale allow-list entries"


def test_loading_a_scene_imports_neither_the_solver_nor_numba():
    code = ("import sys, vlab.scene; vlab.scene.load_scene('specimens/block-neo-hookean.toml'); "
            "print(sorted(m for m in sys.modules if m == 'numba' or m.startswith(('numba.', 'vlab.fe'))))")
    out = subprocess.run([sys.executable, "-c", code], cwd=PACKAGE.parent, capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_importing_the_effects_registry_loads_no_solver():
    code = ("import sys, vlab.effects; "
            "print(sorted(m for m in sys.modules if m == 'numba' or m.startswith(('vlab.fe', 'vlab.measure'))))")
    out = subprocess.run([sys.executable, "-c", code], cwd=PACKAGE.parent, capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_no_import_of_the_package_starts_numba():
    code = ("import sys, vlab.run, vlab.cli, vlab.compare, vlab.verification.suite; "
            "print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], cwd=PACKAGE.parent, capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "False"


def test_importing_vlab_writes_no_environment_variable_and_the_cli_makes_blas_serial():
    import os

    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    code = ("import os, vlab, vlab.scene, vlab.run; print(os.environ.get('OPENBLAS_NUM_THREADS'), "
            "vlab.SERIAL_BLAS)")
    library = subprocess.run([sys.executable, "-c", code], cwd=PACKAGE.parent, capture_output=True, text=True,
                             check=True, env=env).stdout
    assert library.split() == ["None", "False"]
    code = "import os, vlab.cli, vlab; print(os.environ.get('OPENBLAS_NUM_THREADS'), vlab.SERIAL_BLAS)"
    cli = subprocess.run([sys.executable, "-c", code], cwd=PACKAGE.parent, capture_output=True, text=True,
                         check=True, env=env).stdout
    assert cli.split() == ["1", "True"]


def test_the_checker_sees_an_upward_import_and_a_cycle():
    graph = {"vlab.fe.a": {"vlab.report.b"}, "vlab.report.b": {"vlab.fe.a"}}
    assert upward(graph) == [("vlab.fe.a", "vlab.report.b")]
    assert cycles(graph) == [["vlab.fe.a", "vlab.report.b"]]


if __name__ == "__main__":
    top, lazy = imports()
    print("cycles:", cycles(_no_package_self_edges(top)))
    for m, t in upward(top):
        print(f"module-level  {m} -> {t}")
    for m, t in upward(lazy):
        print(f"function-level {m} -> {t}")
