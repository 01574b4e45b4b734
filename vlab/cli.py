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

app = typer.Typer(add_completion=False, no_args_is_help=True, context_settings={"help_option_names": ["-h", "--help"]},
                  help="vlab — a virtual material-testing lab.")
console = Console(stderr=True)

EXIT_OK, EXIT_FAILED, EXIT_INVALID = 0, 1, 2


def _print_version(value: bool) -> None:
    if value:
        from vlab import __version__

        typer.echo(f"vlab {__version__}")
        raise typer.Exit(EXIT_OK)


@app.callback()
def _environment(version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                              help="Print vlab's version and exit.")) -> None:
    """Refuse a bad VLAB_ASSEMBLY_THREADS before any command starts work; warnings print once."""
    from vlab.cli_progress import route_warnings
    from vlab.jit import requested_threads  # numba itself is started only by the solver

    route_warnings(console)

    try:
        requested_threads()
    except ValueError as exc:
        console.print(f"[red]invalid environment[/red] {exc}", highlight=False)
        raise typer.Exit(EXIT_INVALID)


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
        render: bool = typer.Option(True, "--render/--no-render", help="3D renders of the deformed specimen."),
        estimate: bool = typer.Option(True, "--estimate/--no-estimate",
                                      help="Accuracy estimate from one coarser companion solve (mesh.size × 2).")):
    """Run one test and write its report: results.json, curve.csv, PNGs, renders, VTU/PVD, index.html."""
    from vlab.cli_progress import RunProgress, scheduled_levels
    from vlab.report.writer import write_run
    from vlab.run import run_scene

    parsed, text = _load(scene)
    options = _report_options(true, field, single_file, parsed.material.model if gif else None, render)
    out = out or Path("reports") / parsed.name
    if not quiet:
        console.print(f"[bold]{parsed.name}[/bold]: {parsed.material.model}, {parsed.test.kind} "
                      f"to stretch {list(parsed.test.stretch)}", highlight=False)
    with RunProgress(console, scheduled_levels(parsed), quiet) as progress:
        try:
            result = run_scene(parsed, on_level=progress.level)
        except SceneError as exc:  # e.g. a mesh below mesh.min_quality: nothing is written
            progress.bar.stop()
            console.print(f"[red]invalid scene[/red] {exc}", highlight=False)
            raise typer.Exit(EXIT_INVALID)
        if estimate:
            from vlab.study.estimate import accuracy_estimate

            progress.phase("accuracy estimate (mesh × 2)")
            result.extra["accuracy_estimate"] = accuracy_estimate(result)
        progress.phase("report: plots, renders, 3-D")
        data = write_run(result, out, text, options)
        progress.phase("done")
    _print_summary(data)
    _print_estimate(data.get("accuracy_estimate"))
    console.print(f"report: {out / 'index.html'}", highlight=False, soft_wrap=True)
    raise typer.Exit(EXIT_OK if data["converged"] else EXIT_FAILED)


def _print_estimate(est: Optional[dict]) -> None:
    if not est:
        return
    if not est["available"]:
        console.print(f"accuracy estimate not available: {est['reason']}", highlight=False)
        return
    q = est["quantities"]
    parts = ", ".join(f"{k} ± {v['error']:.2g}" for k, v in q.items() if v["error"] is not None)
    console.print(f"accuracy estimate (companion mesh.size {est['companion_mesh_size']:g}, {est['cost_s']:.2f} s): "
                  f"{parts}" + (" — exact by construction (round-off)" if est["exact_by_construction"] else ""),
                  highlight=False)


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
        from vlab.report.explain import by_design_notes

        for key, note in by_design_notes(data).items():  # a difference by design, said where it shows
            console.print(f"  {'nu' if key == 'nu' else key}: {note}", highlight=False)
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
    Console().print(f"  iterative     cg-amg   {amg or 'not installed (pip install pyamg)'}",
                    highlight=False)
    Console().print(f"linear solver in use: {solver_in_use()}", highlight=False)
    from vlab.geometry.cad import gmsh_version

    found_gmsh = gmsh_version() or 'not installed (pip install "vlab[cad]")'
    Console().print(f"  CAD meshing   gmsh     {found_gmsh} (specimen.shape = 'cad')", highlight=False)
    from vlab import jit
    threads = f", {jit.threads()} threads for the tangent" if jit.available() else ""
    Console().print(f"assembly kernels: {jit.in_use()}{threads} (VLAB_KERNEL=numpy: numpy only; "
                    f"VLAB_ASSEMBLY_THREADS=n: n threads)", highlight=False)
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
            out: Optional[Path] = typer.Option(None, "--out", "-o",
                                               help="Output folder (default reports/<scene name>-compare)."),
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
    out = out or Path("reports") / f"{parsed.name}-compare"  # not the `vlab run` report of the scene
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


# --- studies over many runs: sweep (parameter grid) and cost (accuracy against time) -----------

def _execution(workers: int, scheduler: Optional[str]):
    from vlab.study.sweep import Execution

    return Execution(workers=workers, scheduler=scheduler)


def _sweep_with_progress(points, knobs, cache_dir: Path, execution, quiet: bool, what: str):
    """Run the points on Dask with a progress bar of runs done / running / failed."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vlab.study.cache import SummaryCache
    from vlab.study.sweep import run_sweep

    with Progress(TextColumn(f"{what:>8}"), BarColumn(), MofNCompleteColumn(),
                  TextColumn("done · {task.fields[running]} running · {task.fields[failed]} failed"),
                  TimeElapsedColumn(), console=console, disable=quiet) as bar:
        task = bar.add_task(what, total=len(points), running=0, failed=0)

        def progress(done, running, failed, total):
            bar.update(task, completed=done, total=total, running=running, failed=failed)

        return run_sweep(points, knobs, SummaryCache(cache_dir), execution, progress)


@app.command()
def sweep(scene: Path = typer.Argument(..., help="Scene TOML file."),
          sets: list[str] = typer.Option(..., "--set", help="Grid axis section.key=v1,v2,... (repeatable)."),
          out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<name>-sweep)."),
          cache: Path = typer.Option(Path("reports") / ".cache", "--cache", help="Cache folder of run summaries."),
          workers: int = typer.Option(2, "--workers", "-j", min=1, help="Worker processes of the local Dask cluster."),
          scheduler: Optional[str] = typer.Option(None, "--scheduler",
                                                  help="Use an existing Dask cluster, e.g. tcp://HOST:8786."),
          quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress output.")):
    """Run a scene over a parameter grid on Dask; cached runs are not recomputed. Writes a table."""
    from vlab.study.grid import expand_grid, parse_axis
    from vlab.study.summary import RunKnobs
    from vlab.study.table import write_sweep_report

    parsed, _ = _load(scene)
    try:
        points = expand_grid(parsed.source, [parse_axis(s) for s in sets])
    except SceneError as exc:
        console.print(f"[red]invalid option[/red] {exc}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    outcome = _sweep_with_progress(points, RunKnobs(), cache, _execution(workers, scheduler), quiet, "sweep")
    folder = out or Path("reports") / f"{parsed.name}-sweep"
    meta = {"scene": str(scene), "grid": sets, "cache_hits": outcome.cache_hits, "computed": outcome.computed,
            "seconds": outcome.seconds}
    index = write_sweep_report(folder, f"{parsed.name}: sweep", outcome.summaries, meta)
    console.print(f"{len(points)} runs ({outcome.cache_hits} cached, {outcome.computed} computed, "
                  f"{outcome.failed} failed or invalid); table: {index}", highlight=False, soft_wrap=True)
    raise typer.Exit(EXIT_OK if outcome.failed == 0 else EXIT_FAILED)


def _fraction(text: str) -> float:
    """'1%' -> 0.01, '0.01' -> 0.01."""
    try:
        value = float(text[:-1]) / 100.0 if text.strip().endswith("%") else float(text)
    except ValueError:
        value = -1.0
    if not 0.0 < value < 1.0:
        console.print(f"[red]invalid option[/red] --target {text!r}: a relative accuracy in (0, 1), "
                      "e.g. 1% or 0.01", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    return value


def _choices(option: str, text: str, allowed: tuple, convert=str) -> tuple:
    """'1,2' -> (1, 2), each in ``allowed``; otherwise a clear error naming the option."""
    items = [t.strip() for t in text.split(",")]
    try:
        values = tuple(dict.fromkeys(convert(t) for t in items))
    except ValueError:
        values = ()
    if not values or any(v not in allowed for v in values) or "" in items:
        console.print(f"[red]invalid option[/red] {option} {text!r}: a comma-separated subset of "
                      f"{','.join(map(str, allowed))}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    return values


@app.command()
def cost(scene: Path = typer.Argument(..., help="Scene TOML file."),
         target: str = typer.Option("1%", "--target", help="Requested relative accuracy, e.g. 1% or 0.001."),
         levels: int = typer.Option(4, "--levels", min=3, help="Mesh sizes per order and cell."),
         ratio: float = typer.Option(2 ** 0.5, "--ratio", min=1.1, max=4.0,
                                     help="Between successive mesh sizes (the sizes are h0·ratio, h0, h0/ratio, …)."),
         orders: str = typer.Option("1,2", "--orders", help="Element orders of the mesh study, e.g. 1 or 1,2."),
         cells: str = typer.Option("tet,hex", "--cells", help="Cell types of the mesh study, e.g. hex or tet,hex; "
                                   "gmsh-tet: a dogbone's tetrahedra from Gmsh (the cad extra)."),
         out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<name>-cost)."),
         cache: Path = typer.Option(Path("reports") / ".cache", "--cache", help="Cache folder of run summaries."),
         workers: int = typer.Option(2, "--workers", "-j", min=1, help="Worker processes of the local Dask cluster."),
         scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Existing Dask cluster tcp://HOST:PORT."),
         render: bool = typer.Option(False, "--render/--no-render", help="Time the 3D renders in each run's report."),
         quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress output.")):
    """Error against time for mesh size, order, cell, load steps, Newton tolerance and model."""
    from vlab.study.cost import CostOptions, analyse, knob_points
    from vlab.study.cost_report import write_cost_report
    from vlab.study.summary import RunKnobs

    parsed, _ = _load(scene)
    options = CostOptions(levels=levels, ratio=ratio, target=_fraction(target),
                          orders=_choices("--orders", orders, (1, 2), int),
                          cells=_choices("--cells", cells, ("tet", "hex", "gmsh-tet")))
    if "gmsh-tet" in options.cells and parsed.specimen.shape != "dogbone":
        console.print(f"[red]invalid option[/red] --cells gmsh-tet meshes a dogbone; {scene} has specimen.shape = "
                      f"{parsed.specimen.shape!r}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    points = knob_points(parsed, options)
    outcome = _sweep_with_progress(points, RunKnobs(time_report=True, render=render), cache,
                                   _execution(workers, scheduler), quiet, "cost")
    analysis = analyse(parsed, outcome.summaries, options)
    memory = next((s["memory"]["method"] for s in outcome.summaries if s.get("memory")), "")
    meta = {"scene": str(scene), "target": options.target, "levels": levels, "ratio": ratio,
            "orders": list(options.orders), "cells": list(options.cells), "cache_hits": outcome.cache_hits,
            "computed": outcome.computed, "seconds": outcome.seconds, "render": render, "memory_method": memory}
    folder = out or Path("reports") / f"{parsed.name}-cost"
    index = write_cost_report(folder, f"{parsed.name}: what accuracy costs", outcome.summaries, analysis,
                              options.target, meta)
    console.print(analysis.recommendation, highlight=False, soft_wrap=True)
    for q, note in analysis.notes.items():
        console.print(f"  {q}: {note}", highlight=False, soft_wrap=True)
    console.print(f"{len(points)} runs ({outcome.cache_hits} cached, {outcome.computed} computed, "
                  f"{outcome.failed} failed or invalid); report: {index}", highlight=False, soft_wrap=True)
    raise typer.Exit(EXIT_OK)


@app.command()
def stability(fast: bool = typer.Option(False, "--fast", help="Only the fast subset (also run by the tests)."),
              all_cases: bool = typer.Option(False, "--all", help="Every case (the default)."),
              case: Optional[list[str]] = typer.Option(None, "--case", "-c", help="Run only this case (repeatable)."),
              out: Path = typer.Option(Path("reports") / "stability", "--out", "-o", help="Report folder."),
              render: bool = typer.Option(True, "--render/--no-render", help="Render the critical modes."),
              quiet: bool = typer.Option(False, "--quiet", "-q", help="No per-case progress lines.")):
    """Run the stability suite (limit points, refusals, inversion, meshes, buckling vs Euler, dogbone
    extremes); print the table and write reports/stability/ (index.html, results.json, mode renders)."""
    import tempfile
    import time

    from vlab.report.stability_report import write_stability_report
    from vlab.verification.suite import CaseContext, run_suite, select

    if fast and all_cases:
        console.print("[red]invalid option[/red] --fast and --all exclude each other", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    try:
        cases = select(fast_only=fast, names=case)
    except KeyError as exc:
        console.print(f"[red]invalid option[/red] {exc.args[0]}", highlight=False)
        raise typer.Exit(EXIT_INVALID)
    mode = "selected" if case else "fast" if fast else "full"

    def progress(result):
        if not quiet:
            mark = "[green]pass[/green]" if result.passed else "[red]FAIL[/red]"
            console.print(f"  {mark} {result.name} ({result.seconds:.1f} s): {result.outcome.got}", highlight=False)

    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as figures:
        results = run_suite(cases, CaseContext(Path(figures), render), progress)
        total = time.perf_counter() - start
        data = write_stability_report(results, out, mode, total, Path(figures))
    table = Table("case", "expected", "got", "converged", "iterations", "cutbacks", "neg. eig.", "time", "result",
                  title=f"vlab stability ({mode}): {data['passed']} passed, {data['failed']} failed, {total:.1f} s")
    for r in results:
        o = r.outcome
        table.add_row(r.name, r.expected, o.got, "yes" if o.converged else "no", str(o.iterations), str(o.cutbacks),
                      "–" if o.negative_eigenvalues is None else str(o.negative_eigenvalues), f"{r.seconds:.1f} s",
                      "[green]pass[/green]" if r.passed else "[red]FAIL[/red]")
    Console(width=200).print(table)
    console.print(f"report: {out / 'index.html'}", highlight=False, soft_wrap=True)
    raise typer.Exit(EXIT_OK if data["failed"] == 0 else EXIT_FAILED)
