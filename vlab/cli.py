"""The vlab command line: parse, call, print. No physics here."""

from __future__ import annotations

import vlab

vlab.serial_blas_process()  # the CLI owns its process: numpy's BLAS serial from the start (before numpy)

from pathlib import Path
from typing import Optional

import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from vlab.cli_io import (EXIT_FAILED, EXIT_INVALID, EXIT_OK, cache_folder, console, default_scene_path, fail,  # noqa: F401
                         local_workers, report_destination, say, scheduler_address, show)
from vlab.cli_io import results as results_console
from vlab.moduli import ModuliError, from_pair
from vlab.scene import SceneError, load_scene_text

app = typer.Typer(add_completion=False, no_args_is_help=True, context_settings={"help_option_names": ["-h", "--help"]},
                  help="vlab — a virtual material-testing lab.")
FORCE_HELP = ("Replace a non-empty folder vlab did not make (never one holding the scene file, the cache, "
              "the current or the home folder).")
# the options several commands share, spelled once
FORCE = typer.Option(False, "--force", help=FORCE_HELP)
QUIET = typer.Option(False, "--quiet", "-q", help="No progress output.")
TRUE_MEASURES = typer.Option(False, "--true", help="Plot true instead of engineering stress and strain.")
FIELD = typer.Option(None, "--field", help="Render colouring: von-mises, max-stretch, J or max-shear "
                                            "(default: the test kind's: max-shear for torsion, else von-mises).")
WORKERS_HELP = ("Worker processes of the local Dask cluster (default 2, at most the cores); not with "
                "--scheduler.")
SINGLE_FILE = typer.Option(False, "--single-file", help="Inline the images in index.html.")


def _print_version(value: bool) -> None:
    if value:
        from vlab import __version__

        typer.echo(f"vlab {__version__}")
        raise typer.Exit(EXIT_OK)


@app.callback()
def _environment(
    version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                 help="Print vlab's version and exit."),
    kernel: Optional[str] = typer.Option(None, "--kernel", help="auto | numpy (default: VLAB_KERNEL, else auto)"),
    threads: Optional[int] = typer.Option(None, "--threads",
                                          help="assembly threads (default: VLAB_ASSEMBLY_THREADS, else all cores)"),
    linear_solver: Optional[str] = typer.Option(None, "--linear-solver",
                                                help="auto | pardiso | superlu (default: VLAB_LINEAR_SOLVER, else auto)"),
) -> None:
    """Fill the process-wide settings (vlab.settings) from the flags, else the environment,
    refusing a bad value (VLAB_KERNEL, VLAB_ASSEMBLY_THREADS, VLAB_LINEAR_SOLVER or its flag)
    before any command starts work."""
    import dataclasses

    from vlab import settings  # numba itself is started only by the solver
    from vlab.cli_progress import route_warnings

    route_warnings(console)

    try:
        chosen = settings.Settings.from_environment()
        flags = {"kernel": kernel, "assembly_threads": threads, "linear_solver": linear_solver}
        settings.use(dataclasses.replace(chosen, **{k: v for k, v in flags.items() if v is not None}))
    except ValueError as exc:
        fail("invalid environment", exc)


def _load(scene: Optional[Path]):
    """The parsed scene and its text (read once, bounded: vlab.scene.load_scene_text)."""
    path = scene or default_scene_path()
    try:
        return load_scene_text(path)
    except SceneError as exc:
        fail("invalid scene", exc)


def _write(writer, *args):
    """Call a report writer; a folder that cannot be written is exit 2 naming it, a figure worker
    that failed exit 1 with its cause (the report folder is not written in either case)."""
    from vlab.report.figure_worker import FigureWorkerError
    from vlab.report.folder import ReportFolderError

    try:
        return writer(*args)
    except ReportFolderError as exc:
        fail("cannot write report", exc)
    except FigureWorkerError as exc:
        fail("cannot draw the report's figures:", exc, EXIT_FAILED)


@app.command()
def run(scene: Optional[Path] = typer.Argument(None, help="Scene TOML file (default: built-in block test)."),
        out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<scene name>)."),
        quiet: bool = QUIET,
        true: bool = TRUE_MEASURES, field: str | None = FIELD, single_file: bool = SINGLE_FILE,
        gif: bool = typer.Option(False, "--gif", help="Also write an animated GIF of the test."),
        render: bool = typer.Option(True, "--render/--no-render", help="3D renders of the deformed specimen."),
        estimate: bool = typer.Option(True, "--estimate/--no-estimate",
                                      help="Accuracy estimate from one coarser companion solve (mesh.size × 2)."),
        force: bool = FORCE):
    """Run one test and write its report: results.json, curve.csv, PNGs, renders, VTU/PVD, index.html."""
    import contextlib

    from vlab import settings
    from vlab.cli_progress import RunProgress, scheduled_ramps
    from vlab.report.figure_worker import FigureWorker, wanted
    from vlab.report.writer import write_run

    parsed, text = _load(scene)
    options = _report_options(true, field, single_file, parsed.material.model if gif else None, render)
    dest = report_destination(out or Path("reports") / parsed.name, force, scene or None)
    if not quiet:
        _announce(parsed)
    # the figures' process imports matplotlib on the other core while this one solves
    worker = FigureWorker() if wanted(settings.current().figure_process) else None
    with worker or contextlib.nullcontext(), RunProgress(console, scheduled_ramps(parsed), quiet) as progress:
        result = _solved(parsed, progress, estimate)
        progress.phase("report: plots, renders, 3-D")
        data = _write(write_run, result, dest, text, options, worker)
        progress.phase("done")
    _print_summary(data)
    _print_estimate(data.get("accuracy_estimate"))
    show(f"report: {dest.path / 'index.html'}")
    raise typer.Exit(EXIT_OK if data["converged"] else EXIT_FAILED)


def _announce(parsed) -> None:
    from vlab.loading.kinds import kind_of

    kind = kind_of(parsed.test)
    say((parsed.name, "bold"), f": {parsed.material.model}, {parsed.test.kind} "
        f"to {kind.load_key} {list(parsed.test.targets)}")


def _solved(parsed, progress, estimate: bool, on_level=None):
    """The run (levels shown on ``progress``, or handed to ``on_level``) and, if asked, its accuracy
    estimate; a scene the run refuses (e.g. a mesh below mesh.min_quality) is exit 2 with nothing
    written."""
    from vlab.run import run_scene

    try:
        result = run_scene(parsed, on_level=on_level or progress.level)
    except SceneError as exc:
        progress.bar.stop()
        fail("invalid scene", exc)
    if estimate:
        from vlab.study.estimate import accuracy_estimate

        progress.phase("accuracy estimate (mesh × 2)")
        result.diagnostics.accuracy_estimate = accuracy_estimate(result)
    return result


@app.command()
def fit(fitfile: Path = typer.Argument(..., help="Fit file (TOML): data sets, model, options."),
        out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<name>-fit)."),
        models: Optional[str] = typer.Option(None, "--models",
                                             help="Fit and rank several models, e.g. mooney-rivlin,yeoh,ogden-3."),
        force: bool = FORCE,
        workers: Optional[int] = typer.Option(None, "--workers", "-j", min=1,
                                              help="FE-in-the-loop solves on a local Dask cluster of N processes."),
        scheduler: Optional[str] = typer.Option(None, "--scheduler",
                                                help="FE-in-the-loop solves on an existing Dask cluster tcp://HOST:PORT."),
        export: Optional[str] = typer.Option(None, "--export",
                                             help="Also write the card for these solvers into OUT/cards/, e.g. abaqus,ansys,felupe.")):
    """Fit a material card to measured curves: parameters with intervals, stability, the card (fit.json, index.html)."""
    from vlab.identify.command import fit_command

    execution = _execution(workers, scheduler, default=None)
    raise typer.Exit(fit_command(fitfile, out, models, console, force, execution, export, results_console))


def _print_estimate(est: Optional[dict]) -> None:
    if not est:
        return
    if not est["available"]:
        show(f"accuracy estimate not available: {est['reason']}")
        return
    q = est["quantities"]
    parts = ", ".join(f"{k} ± {v['error']:.2g}" for k, v in q.items() if v["error"] is not None)
    show(f"accuracy estimate (companion mesh.size {est['companion_mesh_size']:g}, {est['cost_s']:.2f} s): "
         f"{parts}" + (" — exact by construction (round-off): the mesh adds no error to E, ν, stress"
                       if est["exact_by_construction"] else ""))


def _print_summary(data: dict) -> None:
    from vlab.report.kind_rows import kind_of_data

    m, kind = data["measured"], kind_of_data(data)
    key = kind.load_key  # the control the test drives: stretch, shear or twist
    if data["converged"]:
        show(("completed", "green"), f" in {data['timing']['total_s']:.2f} s, "
             f"{sum(data['solver']['newton_iterations'])} Newton iterations, {data['mesh']['dofs']} DOFs")
    else:
        f = data["failure"]
        show(("test stopped", "red"), f" at step {f['step']}, {key} {f['stretch']}: {f['reason']}; "
             f"last converged {key} {f['last_converged_stretch']}; "
             f"residual history {[f'{r:.2e}' for r in f['residual_history']]}")
    if m["E"] is not None:
        show(f"measured E = {m['E']:.6g} MPa, nu = {m['nu']:.6g} "
             f"(input E = {data['input']['E']:.6g}, nu = {data['input']['nu']:.6g})")
        from vlab.report.explain import by_design_notes

        for key, note in by_design_notes(data, brief=True).items():  # a difference by design, said where it shows
            show(f"  {key}: {note}")
    elif kind.measures_E:
        show(f"E and nu {m['note']}")
    else:  # the kind's own sentence: "G not measured: …", "simple shear: E and nu are not measured; …"
        show(m["note"])


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
        fail("invalid input", exc)
    table = Table("constant", "value", "unit")
    units = {"nu": "1"}
    for key, value in result.as_dict().items():
        table.add_row(key, f"{value:.10g}", units.get(key, "MPa"))
    results_console.print(table)


@app.command()
def info():
    """Versions and the linear solver in use."""
    import numpy
    import scipy
    import skfem

    from vlab import __version__
    from vlab.fe.linsolve import available_solvers, solver_in_use

    show(f"vlab {__version__}; numpy {numpy.__version__}, scipy {scipy.__version__}, "
         f"scikit-fem {skfem.__version__}")
    found = available_solvers()
    for name, version in found.items():
        show(f"  linear solver {name:8s} {version or 'not installed'}")
    from vlab.fe.iterative import CROSSOVER
    from vlab.fe.iterative import available as amg_available

    amg = amg_available()
    show(f"  iterative     cg-amg   {amg or 'not installed (pip install pyamg)'}")
    show(f"linear solver in use: {solver_in_use()}")
    from vlab.geometry.cad import gmsh_version

    found_gmsh = gmsh_version() or 'not installed (pip install "vlab[cad]")'
    show(f"  CAD meshing   gmsh     {found_gmsh} (specimen.shape = 'cad')")
    from vlab import jit, settings
    config = settings.current()  # what the CLI installed from the flags and the environment
    threads = f", {jit.threads(config)} threads for the tangent" if jit.available(config) else ""
    show(f"assembly kernels: {jit.in_use(config)}{threads} (VLAB_KERNEL=numpy: numpy only; "
         f"VLAB_ASSEMBLY_THREADS=n: n threads)")
    if amg:
        show(f"  [solver] linear = 'auto': CG + AMG for Newton corrections from "
             f"{CROSSOVER.get(solver_in_use(), CROSSOVER['superlu']):,} free DOFs on "
             f"(stability checks always factorize directly)")


def _report_options(true: bool, field: str | None, single_file: bool, gif_model, render: bool):
    from vlab.post.fields import FIELDS
    from vlab.report.writer import ReportOptions

    if field is not None and field not in FIELDS:
        fail("invalid option", f"--field {field!r}; allowed: {', '.join(FIELDS)}")
    return ReportOptions(true_measures=true, field=field, single_file=single_file, gif_model=gif_model,
                         render=render)


def _parse_models(text: str | None, scene) -> tuple[str, ...]:
    """--models (vlab.compare.chosen_models), exit 2 naming a bad one."""
    from vlab.compare import chosen_models

    try:
        return chosen_models(scene, text)
    except SceneError as exc:
        fail("invalid option", exc)


@app.command()
def compare(scene: Optional[Path] = typer.Argument(None, help="Scene TOML file (default: built-in block test)."),
            models: Optional[str] = typer.Option(None, "--models", "-m",
                                                 help="Comma-separated [compare.<label>] labels of the "
                                                      "scene and/or model names (linear, stvk, "
                                                      "stvk-volumetric, neo-hookean, spring-network take "
                                                      "the scene's E, nu); default: the scene's labels, "
                                                      "else linear,stvk,neo-hookean."),
            out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<scene name>-compare)."),
            workers: Optional[int] = typer.Option(None, "--workers", "-j", min=1,
                                                  help="Parallel processes (default: one per core)."),
            quiet: bool = QUIET,
            true: bool = TRUE_MEASURES, field: str | None = FIELD, single_file: bool = SINGLE_FILE,
            gif: Optional[str] = typer.Option(None, "--gif", help="Animate this model's test as a GIF."),
            render: bool = typer.Option(True, "--render/--no-render", help="3D renders of the deformed specimens."),
            force: bool = FORCE):
    """Run one scene with several material models side by side and write a comparison report."""
    from vlab.report.writer import write_report

    parsed, text = _load(scene)
    chosen = _checked_models(models, parsed, gif)
    options = _report_options(true, field, single_file, gif, render)
    dest = report_destination(out or Path("reports") / f"{parsed.name}-compare", force, scene or None)  # not the run's
    outcomes = _compared(parsed, chosen, local_workers(workers, None, default=None), quiet)
    _write(write_report, outcomes, dest, parsed, text, options)
    for outcome in outcomes:
        if not quiet:
            show((outcome.model, "bold"))
            _print_summary(outcome.data)
    show(f"report: {dest.path / 'index.html'}")
    raise typer.Exit(EXIT_OK if all(o.data["converged"] for o in outcomes) else EXIT_FAILED)


def _checked_models(models: Optional[str], parsed, gif: Optional[str]) -> list[str]:
    """The --models to run, each a valid scene with the scene's constants (exit 2 otherwise)."""
    from vlab.compare import scene_for_model

    chosen = _parse_models(models, parsed)
    if gif is not None and gif not in chosen:
        fail("invalid option", f"--gif {gif!r} is not among --models {', '.join(chosen)}")
    try:
        for model in chosen:
            scene_for_model(parsed, model)
    except SceneError as exc:
        fail("invalid scene", exc)
    return chosen


def _compared(parsed, chosen: list[str], workers: Optional[int], quiet: bool) -> list:
    """Every model's outcome, run in worker processes, with a progress bar per model."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vlab.compare import compare_models

    with Progress(TextColumn("{task.description:>16}"), BarColumn(), MofNCompleteColumn(),
                  TextColumn("load levels"), TimeElapsedColumn(), console=console, disable=quiet) as bar:
        tasks = {m: bar.add_task(m, total=None) for m in chosen}
        return compare_models(parsed, chosen, workers,
                              lambda m, done, total: bar.update(tasks[m], completed=done, total=total))


# --- studies over many runs: sweep (parameter grid) and cost (accuracy against time) -----------

def _execution(workers: Optional[int], scheduler: Optional[str], default: Optional[int] = 2):
    """Where the runs execute (vlab.study.sweep.Execution): a local cluster of --workers processes
    (else ``default``; capped at the cores) or the --scheduler (checked); None when neither is
    given and ``default`` is None. Both given: exit 2 (vlab.cli_io.local_workers)."""
    from vlab.study.sweep import Execution

    scheduler = scheduler_address(scheduler)
    n = local_workers(workers, scheduler, default)
    if scheduler is None and n is None:
        return None
    return Execution(workers=n or 1, scheduler=scheduler)


def _sweep_with_progress(points, knobs, cache_dir: Path, execution, quiet: bool, what: str):
    """Run the points on Dask with a progress bar of runs done / running / failed."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vlab.study.cache import SummaryCache
    from vlab.study.scheduler import SchedulerError
    from vlab.study.sweep import run_sweep

    with Progress(TextColumn(f"{what:>8}"), BarColumn(), MofNCompleteColumn(),
                  TextColumn("done · {task.fields[running]} running · {task.fields[failed]} failed"),
                  TimeElapsedColumn(), console=console, disable=quiet) as bar:
        task = bar.add_task(what, total=len(points), running=0, failed=0)

        def progress(done, running, failed, total):
            bar.update(task, completed=done, total=total, running=running, failed=failed)

        try:
            return run_sweep(points, knobs, SummaryCache(cache_dir), execution, progress)
        except SchedulerError as exc:
            bar.stop()
            fail("invalid option", exc)


def _study_exit(outcome, all_failed_only: bool = False) -> int:
    """Exit 2 when every point is invalid (the scene itself is), 1 when any (or, for ``cost``, every)
    point failed or is invalid, else 0."""
    statuses = [s["status"] for s in outcome.summaries]
    if statuses and all(s == "invalid" for s in statuses):
        first = outcome.summaries[0].get("diagnosis")
        say(("every run is invalid", "red"), f": {first}")
        return EXIT_INVALID
    bad = [s != "ok" for s in statuses]
    return EXIT_FAILED if (all(bad) if all_failed_only else any(bad)) else EXIT_OK


@app.command()
def sweep(scene: Path = typer.Argument(..., help="Scene TOML file."),
          sets: list[str] = typer.Option(..., "--set", help="Grid axis section.key=v1,v2,... (repeatable)."),
          out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<name>-sweep)."),
          cache: Path = typer.Option(Path("reports") / ".cache", "--cache", help="Cache folder of run summaries."),
          workers: Optional[int] = typer.Option(None, "--workers", "-j", min=1, help=WORKERS_HELP),
          scheduler: Optional[str] = typer.Option(None, "--scheduler",
                                                  help="Use an existing Dask cluster, e.g. tcp://HOST:8786."),
          quiet: bool = QUIET,
          force: bool = FORCE):
    """Run a scene over a parameter grid on Dask; cached runs are not recomputed. Writes a table."""
    from vlab.study.commands import grid_points, sweep_meta
    from vlab.study.summary import RunKnobs
    from vlab.study.table import write_sweep_report

    parsed, _ = _load(scene)
    execution = _execution(workers, scheduler)
    try:
        points = grid_points(parsed, sets)
    except SceneError as exc:
        fail("invalid option", exc)
    cache = cache_folder(cache)
    dest = report_destination(out or Path("reports") / f"{parsed.name}-sweep", force, scene, [cache])
    outcome = _sweep_with_progress(points, RunKnobs(), cache, execution, quiet, "sweep")
    meta = sweep_meta(str(scene), sets, outcome)
    index = _write(write_sweep_report, dest, f"{parsed.name}: sweep", outcome.summaries, meta)
    show(f"{len(points)} runs ({outcome.cache_hits} cached, {outcome.computed} computed, "
         f"{outcome.failed} failed or invalid); table: {index}")
    raise typer.Exit(_study_exit(outcome))


def _fraction(text: str) -> float:
    """'1%' -> 0.01, '0.01' -> 0.01."""
    try:
        value = float(text[:-1]) / 100.0 if text.strip().endswith("%") else float(text)
    except ValueError:
        value = -1.0
    if not 0.0 < value < 1.0:
        fail("invalid option", f"--target {text!r}: a relative accuracy in (0, 1), e.g. 1% or 0.01")
    return value


def _choices(option: str, text: str, allowed: tuple, convert=str) -> tuple:
    """'1,2' -> (1, 2), each in ``allowed``; otherwise a clear error naming the option."""
    items = [t.strip() for t in text.split(",")]
    try:
        values = tuple(dict.fromkeys(convert(t) for t in items))
    except ValueError:
        values = ()
    if not values or any(v not in allowed for v in values) or "" in items:
        fail("invalid option", f"{option} {text!r}: a comma-separated subset of {','.join(map(str, allowed))}")
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
         workers: Optional[int] = typer.Option(None, "--workers", "-j", min=1, help=WORKERS_HELP),
         scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Existing Dask cluster tcp://HOST:PORT."),
         render: bool = typer.Option(False, "--render/--no-render", help="Time the 3D renders in each run's report."),
         quiet: bool = QUIET,
         force: bool = FORCE):
    """Error against time for mesh size, order, cell, load steps, Newton tolerance and model."""
    from vlab.study.commands import cost_meta
    from vlab.study.cost import analyse, fixed_mesh_note, knob_points
    from vlab.study.cost_report import write_cost_report
    from vlab.study.summary import RunKnobs

    parsed, _ = _load(scene)
    execution = _execution(workers, scheduler)
    options = _cost_options(scene, parsed, levels, ratio, target, orders, cells)
    points = knob_points(parsed, options)
    if fixed_mesh_note(parsed) is not None and not quiet:
        say(fixed_mesh_note(parsed))
    cache = cache_folder(cache)
    dest = report_destination(out or Path("reports") / f"{parsed.name}-cost", force, scene, [cache])
    outcome = _sweep_with_progress(points, RunKnobs(time_report=True, render=render), cache, execution, quiet, "cost")
    analysis = analyse(parsed, outcome.summaries, options)
    meta = cost_meta(str(scene), parsed, options, outcome, render)
    index = _write(write_cost_report, dest, f"{parsed.name}: what accuracy costs", outcome.summaries, analysis,
                   options.target, meta)
    _print_cost(analysis, len(points), outcome, index)
    raise typer.Exit(_study_exit(outcome, all_failed_only=True))


def _print_cost(analysis, runs: int, outcome, index) -> None:
    """The recommendation, the note of each quantity and how many runs were cached or computed."""
    show(analysis.recommendation)
    for q, note in analysis.notes.items():
        show(f"  {q}: {note}")
    show(f"{runs} runs ({outcome.cache_hits} cached, {outcome.computed} computed, "
         f"{outcome.failed} failed or invalid); report: {index}")


def _cost_options(scene: Path, parsed, levels: int, ratio: float, target: str, orders: str, cells: str):
    """The study's CostOptions from the flags (vlab.study.commands.cost_options; exit 2 naming a bad one)."""
    from vlab.study.commands import CELLS, ORDERS, cost_options

    try:
        return cost_options(parsed, levels, ratio, _fraction(target), _choices("--orders", orders, ORDERS, int),
                            _choices("--cells", cells, CELLS), origin=str(scene))
    except SceneError as exc:
        fail("invalid option", exc)


@app.command()
def stability(fast: bool = typer.Option(False, "--fast", help="Only the fast subset (also run by the tests)."),
              all_cases: bool = typer.Option(False, "--all", help="Every case (the default)."),
              case: Optional[list[str]] = typer.Option(None, "--case", "-c", help="Run only this case (repeatable)."),
              out: Path = typer.Option(Path("reports") / "stability", "--out", "-o", help="Report folder."),
              render: bool = typer.Option(True, "--render/--no-render", help="Render the critical modes."),
              quiet: bool = typer.Option(False, "--quiet", "-q", help="No per-case progress lines."),
              force: bool = FORCE):
    """Run the stability suite (limit points, refusals, inversion, meshes, buckling vs Euler, dogbone
    extremes); print the table and write reports/stability/ (index.html, results.json, mode renders)."""
    import tempfile

    from vlab.report.stability_report import write_stability_report
    from vlab.verification.suite import CaseContext, run_timed, select, suite_mode

    if fast and all_cases:
        fail("invalid option", "--fast and --all exclude each other")
    try:
        cases = select(fast_only=fast, names=case)
    except KeyError as exc:
        fail("invalid option", exc.args[0])
    dest = report_destination(out, force)
    mode = suite_mode(fast, case)

    def progress(result):
        if not quiet:
            mark = ("pass", "green") if result.passed else ("FAIL", "red")
            say("  ", mark, f" {result.name} ({result.seconds:.1f} s): {result.outcome.got}")

    with tempfile.TemporaryDirectory() as figures:
        results, total = run_timed(cases, CaseContext(Path(figures), render), progress)
        data = _write(write_stability_report, results, dest, mode, total, Path(figures))
    Console(width=200, markup=False, highlight=False).print(_stability_table(results, data, mode, total))
    show(f"report: {dest.path / 'index.html'}")
    raise typer.Exit(EXIT_OK if data["failed"] == 0 else EXIT_FAILED)


def _stability_table(results, data: dict, mode: str, total: float) -> Table:
    table = Table("case", "expected", "got", "converged", "iterations", "cutbacks", "neg. eig.", "time", "result",
                  title=f"vlab stability ({mode}): {data['passed']} passed, {data['failed']} failed, {total:.1f} s")
    for r in results:
        o = r.outcome
        table.add_row(*map(Text, (r.name, r.expected, o.got, "yes" if o.converged else "no", str(o.iterations),
                                  str(o.cutbacks), "–" if o.negative_eigenvalues is None else
                                  str(o.negative_eigenvalues), f"{r.seconds:.1f} s")),
                      Text("pass", "green") if r.passed else Text("FAIL", "red"))
    return table


@app.command("export")
def export_card(source: Path = typer.Argument(..., help="A vlab fit folder, its fit.json or card.toml, or a scene TOML."),
                to: str = typer.Option(..., "--to", help="abaqus, calculix, ansys, lsdyna, febio or felupe (comma list)."),
                out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output file (default abaqus.inp, ansys.mac, ...)."),
                units: str = typer.Option("mm", "--units", help="mm (N, mm, MPa, s, t/mm³) or SI (N, m, Pa, s, kg/m³)."),
                elastic_only: bool = typer.Option(False, "--elastic-only", help="Drop a scene's viscoelastic/Mullins parts."),
                force: bool = typer.Option(False, "--force", help="Replace a file vlab did not write.")):
    """Write a material card for another solver, exactly in its convention (or refuse, exit 2)."""
    from vlab.export.command import export_command

    raise typer.Exit(export_command(source, to, out, units, elastic_only, force, say, show))


@app.command("import-card")
def import_card(file: Path = typer.Argument(..., help="An Abaqus/CalculiX, ANSYS, LS-DYNA, FEBio or FElupe card."),
                out: Optional[Path] = typer.Option(None, "--out", "-o", help="The vlab card (default card.toml)."),
                solver: Optional[str] = typer.Option(None, "--from", help="The format (default: from the content)."),
                units: Optional[str] = typer.Option(None, "--units", help="mm or SI (default: the vlab header's, else mm)."),
                force: bool = typer.Option(False, "--force", help="Replace a file vlab did not write.")):
    """Read a solver's material card into a vlab [material] card."""
    from vlab.export.command import import_command

    raise typer.Exit(import_command(file, out, solver, units, force, say, show))
@app.command()
def design(fitfile: Path = typer.Argument(..., help="Fit file (TOML): homogeneous data sets, or specimen data with [fe]."),
           candidates: Optional[str] = typer.Option(None, "--candidates", help="Test kinds to plan, e.g. "
                                                    "uniaxial,equibiaxial,planar,simple-shear (the default; none for specimen data)."),
           ranges: Optional[str] = typer.Option(None, "--range", help="Ranges, e.g. uniaxial=1.05:3,planar=1.05:2.5, "
                                                "specimen=0.05:0.5 (extensometer strain; default: the fitted range, "
                                                "else the data's largest I1)."),
           points: int = typer.Option(20, "--points", help="Points per planned test."),
           combine: Optional[int] = typer.Option(None, "--combine", help="Largest number of tests combined "
                                                 "(default: 3, or the number of candidate tests if fewer)."),
           noise: Optional[float] = typer.Option(None, "--noise", help="Reading scatter (relative, or MPa or N, as the fit's "
                                                 "residual); default: the fit's residual scatter."),
           expect: Optional[str] = typer.Option(None, "--expect", help="Expected constants, e.g. C10=0.3,C01=0.05 "
                                                  "(default: the fitted card)."),
           specimens: Optional[str] = typer.Option(None, "--specimens", help="FE in the loop: other specimen scenes "
                                                   "to plan beside fe.scene, e.g. a.toml,b.toml."),
           gauges: Optional[str] = typer.Option(None, "--gauge-lengths", help="FE in the loop: extensometer gauge "
                                                "lengths (mm) to plan beside each scene's own, e.g. 10,20."),
           elongation_sd: Optional[float] = typer.Option(None, "--extensometer-std", help="FE in the loop: the "
                                                         "extensometer's elongation scatter (mm, sd; default 0)."),
           out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<name>-design)."),
           force: bool = FORCE):
    """Which test next: Fisher information, predicted standard errors, D/A-optimality (design.json, index.html)."""
    from vlab.identify.design_command import design_command

    raise typer.Exit(design_command(fitfile, out, candidates, ranges, points, combine, noise, console, force,
                                    expect, specimens, gauges, elongation_sd, results_console))


@app.command()
def budget(scene: Path = typer.Argument(..., help="Scene TOML file (a uniaxial block or dogbone; [uncertainty] table)."),
           samples: Optional[int] = typer.Option(None, "--samples", help="Monte Carlo samples (default: "
                                                 "uncertainty.samples, else 200)."),
           workers: Optional[int] = typer.Option(None, "--workers", "-j", min=1, help=WORKERS_HELP),
           scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Existing Dask cluster tcp://HOST:PORT."),
           out: Optional[Path] = typer.Option(None, "--out", "-o", help="Output folder (default reports/<name>-budget)."),
           cache: Path = typer.Option(Path("reports") / ".cache", "--cache", help="Cache folder of run summaries."),
           quiet: bool = QUIET,
           force: bool = FORCE):
    """Uncertainty budget of E and ν: Monte Carlo of virtual tests, GUM sensitivities, Sobol indices."""
    from vlab.uncertainty.command import budget_command

    budget_command(scene, samples, workers, scheduler, out, cache, quiet, force)
@app.command()
def dic(reference: Path = typer.Argument(..., help="The reference grey image (8- or 16-bit PNG or TIFF)."),
        deformed: list[Path] = typer.Argument(..., help="The deformed image(s), in sequence order."),
        subset: int = typer.Option(31, "--subset", help="Subset side (px, odd)."),
        step: int = typer.Option(10, "--step", help="Step between subset centres (px)."),
        strain_window: int = typer.Option(5, "--strain-window", help="Strain window (grid points, odd)."),
        search: int = typer.Option(20, "--search", help="Integer search radius (px)."),
        out: Path = typer.Option(Path("reports") / "dic", "--out", "-o", help="Report folder."),
        quiet: bool = QUIET, force: bool = FORCE):
    """Subset-based 2-D DIC of an image pair or sequence: DIR/fields/<stem>.csv, DIR/dic.json and
    index.html with the maps (docs/dic.md)."""
    from vlab.dic.cli import run_dic

    run_dic(reference, deformed, dict(subset=subset, step=step, strain_window=strain_window, search=search),
            report_destination(out, force), quiet)
