"""The vlab command line: parse, call, print. No physics here."""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table

from vlab.moduli import ModuliError, from_pair
from vlab.scene import SceneError, load_scene

app = typer.Typer(add_completion=False, no_args_is_help=True,
                  help="vlab — a virtual material-testing lab.")
console = Console(stderr=True)

EXIT_OK, EXIT_FAILED, EXIT_INVALID = 0, 1, 2


def default_scene_path() -> Path:
    return Path(str(resources.files("vlab") / "scenes" / "default.toml"))


def _load(scene: Optional[Path]):
    path = scene or default_scene_path()
    try:
        return load_scene(path), path.read_text(encoding="utf-8")
    except SceneError as exc:
        console.print(f"[red]invalid scene[/red] {exc}", highlight=False)
        raise typer.Exit(EXIT_INVALID)


@app.command()
def run(scene: Optional[Path] = typer.Argument(None, help="Scene TOML file (default: built-in block test)."),
        out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<scene name>)."),
        quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress output.")):
    """Run one test and write results.json, curve.csv, a stress–strain PNG and index.html."""
    from vlab.report.writer import write_run
    from vlab.run import run_scene

    parsed, text = _load(scene)
    out = out or Path("reports") / parsed.name
    n_levels = [0]

    def progress(level):
        n_levels[0] += 1
        if not quiet:
            console.print(f"  level {n_levels[0]:3d}  t = {level.t:.4f}  Newton iterations {level.iterations}",
                          highlight=False)

    if not quiet:
        console.print(f"[bold]{parsed.name}[/bold]: {parsed.material.model}, {parsed.test.kind} "
                      f"to stretch {list(parsed.test.stretch)}", highlight=False)
    result = run_scene(parsed, on_level=progress)
    data = write_run(result, out, text)
    _print_summary(data)
    console.print(f"report: {out / 'index.html'}", highlight=False)
    raise typer.Exit(EXIT_OK if data["converged"] else EXIT_FAILED)


def _print_summary(data: dict) -> None:
    m = data["measured"]
    if data["converged"]:
        console.print(f"[green]completed[/green] in {data['timing']['total_s']:.2f} s, "
                      f"{sum(data['solver']['newton_iterations'])} Newton iterations, "
                      f"{data['mesh']['dofs']} DOFs", highlight=False)
    else:
        f = data["failure"]
        console.print(f"[red]test stopped[/red] at step {f['step']}, stretch {f['stretch']}: {f['reason']}; "
                      f"last converged stretch {f['last_converged_stretch']}; "
                      f"residual history {[f'{r:.2e}' for r in f['residual_history']]}", highlight=False)
    if m["E"] is not None:
        console.print(f"measured E = {m['E']:.6g} MPa, nu = {m['nu']:.6g} "
                      f"(input E = {data['input']['E']:.6g}, nu = {data['input']['nu']:.6g})", highlight=False)
    else:
        console.print(f"E and nu {m['note']}", highlight=False)


@app.command()
def moduli(E: Optional[float] = typer.Option(None, "--E"), nu: Optional[float] = typer.Option(None, "--nu"),
           lmbda: Optional[float] = typer.Option(None, "--lambda"), mu: Optional[float] = typer.Option(None, "--mu"),
           K: Optional[float] = typer.Option(None, "--K"), M: Optional[float] = typer.Option(None, "--M"),
           root: str = typer.Option("plus", help="Root of the (E, M) pair: plus (nu >= 0) or minus.")):
    """Print all six isotropic elastic constants from any two of them."""
    given = {k: v for k, v in {"E": E, "nu": nu, "lambda": lmbda, "mu": mu, "K": K, "M": M}.items()
             if v is not None}
    try:
        result = from_pair(given, root=root)
    except ModuliError as exc:
        console.print(f"[red]invalid input[/red] {exc}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    table = Table("constant", "value", "unit")
    units = {"nu": "1"}
    for key, value in result.as_dict().items():
        table.add_row(key, f"{value:.10g}", units.get(key, "MPa"))
    Console().print(table)


@app.command()
def info():
    """Versions and the linear solver in use."""
    import numpy
    import scipy
    import skfem

    from vlab import __version__
    from vlab.fe.linsolve import available_solvers, solver_in_use

    Console().print(f"vlab {__version__}; numpy {numpy.__version__}, scipy {scipy.__version__}, "
                    f"scikit-fem {skfem.__version__}")
    found = available_solvers()
    for name, version in found.items():
        Console().print(f"  linear solver {name:8s} {version or 'not installed'}", highlight=False)
    Console().print(f"linear solver in use: {solver_in_use()}", highlight=False)
