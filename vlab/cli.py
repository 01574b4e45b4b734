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
        quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress output."),
        true: bool = typer.Option(False, "--true", help="Plot true instead of engineering stress and strain."),
        field: str = typer.Option("von-mises", "--field", help="Render colouring: von-mises, max-stretch or J."),
        single_file: bool = typer.Option(False, "--single-file", help="Inline the images in index.html."),
        gif: bool = typer.Option(False, "--gif", help="Also write an animated GIF of the test."),
        render: bool = typer.Option(True, "--render/--no-render", help="3D renders of the deformed specimen.")):
    """Run one test and write its report: results.json, curve.csv, PNGs, renders, VTU/PVD, index.html."""
    from vlab.report.writer import write_run
    from vlab.run import run_scene

    parsed, text = _load(scene)
    options = _report_options(true, field, single_file, parsed.material.model if gif else None, render)
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
    try:
        result = run_scene(parsed, on_level=progress)
    except SceneError as exc:  # e.g. a mesh below mesh.min_quality: nothing is written
        console.print(f"[red]invalid scene[/red] {exc}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    data = write_run(result, out, text, options)
    _print_summary(data)
    console.print(f"report: {out / 'index.html'}", highlight=False, soft_wrap=True)
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
    from vlab.fe.iterative import CROSSOVER
    from vlab.fe.iterative import available as amg_available

    amg = amg_available()
    Console().print(f"  iterative     cg-amg   {amg or 'not installed (pip install vlab[amg])'}",
                    highlight=False)
    Console().print(f"linear solver in use: {solver_in_use()}", highlight=False)
    if amg:
        Console().print(f"  \\[solver] linear = 'auto': CG + AMG for Newton corrections from "
                        f"{CROSSOVER.get(solver_in_use(), CROSSOVER['superlu']):,} free DOFs on "
                        f"(stability checks always factorize directly)", highlight=False)


def _report_options(true: bool, field: str, single_file: bool, gif_model, render: bool):
    from vlab.post.fields import FIELDS
    from vlab.report.writer import ReportOptions

    if field not in FIELDS:
        console.print(f"[red]invalid option[/red] --field {field!r}; allowed: {', '.join(FIELDS)}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    return ReportOptions(true_measures=true, field=field, single_file=single_file, gif_model=gif_model,
                         render=render)


def _parse_models(text: str) -> tuple[str, ...]:
    from vlab.scene import MODELS

    models = tuple(dict.fromkeys(m.strip() for m in text.split(",") if m.strip()))
    bad = [m for m in models if m not in MODELS]
    if not models or bad:
        console.print(f"[red]invalid option[/red] --models {text!r}: unknown {', '.join(map(repr, bad)) or 'empty list'}; "
                      f"allowed: {', '.join(MODELS)} (comma-separated)", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    return models


@app.command()
def compare(scene: Optional[Path] = typer.Argument(None, help="Scene TOML file (default: built-in block test)."),
            models: str = typer.Option("linear,stvk,neo-hookean", "--models", "-m",
                                       help="Comma-separated models (linear, stvk, stvk-volumetric, "
                                            "neo-hookean, spring-network)."),
            out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<scene name>)."),
            workers: Optional[int] = typer.Option(None, "--workers", "-j", min=1,
                                                  help="Parallel processes (default: one per core)."),
            quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress output."),
            true: bool = typer.Option(False, "--true", help="Plot true instead of engineering stress and strain."),
            field: str = typer.Option("von-mises", "--field", help="Render colouring: von-mises, max-stretch or J."),
            single_file: bool = typer.Option(False, "--single-file", help="Inline the images in index.html."),
            gif: Optional[str] = typer.Option(None, "--gif", help="Animate this model's test as a GIF."),
            render: bool = typer.Option(True, "--render/--no-render", help="3D renders of the deformed specimens.")):
    """Run one scene with several material models side by side and write a comparison report."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vlab.compare import compare_models, scene_for_model
    from vlab.report.writer import write_report

    parsed, text = _load(scene)
    chosen = _parse_models(models)
    if gif is not None and gif not in chosen:
        console.print(f"[red]invalid option[/red] --gif {gif!r} is not among --models {', '.join(chosen)}",
                      highlight=False)
        raise typer.Exit(EXIT_INVALID)
    try:
        for model in chosen:
            scene_for_model(parsed, model)
    except SceneError as exc:
        console.print(f"[red]invalid scene[/red] {exc}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    options = _report_options(true, field, single_file, gif, render)
    out = out or Path("reports") / parsed.name
    with Progress(TextColumn("{task.description:>16}"), BarColumn(), MofNCompleteColumn(),
                  TextColumn("load levels"), TimeElapsedColumn(), console=console, disable=quiet) as bar:
        tasks = {m: bar.add_task(m, total=None) for m in chosen}
        outcomes = compare_models(parsed, chosen, workers,
                                  lambda m, done, total: bar.update(tasks[m], completed=done, total=total))
    write_report(outcomes, out, parsed, text, options)
    for outcome in outcomes:
        if not quiet:
            console.print(f"[bold]{outcome.model}[/bold]", highlight=False)
            _print_summary(outcome.data)
    console.print(f"report: {out / 'index.html'}", highlight=False, soft_wrap=True)
    raise typer.Exit(EXIT_OK if all(o.data["converged"] for o in outcomes) else EXIT_FAILED)
