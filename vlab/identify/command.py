"""`vlab fit`: read, fit, write, print; the exit code (docs/fit-exit-codes.md) says converged with
a trustworthy card (0), not converged (1), invalid input (2), converged but the card is not
trustworthy (3: a constant without an interval, or a card unstable over the fitted ranges)."""

from __future__ import annotations

from pathlib import Path

from rich.console import Console
from rich.text import Text

from vlab.cli_io import EXIT_FAILED, EXIT_OK, EXIT_UNTRUSTED
from vlab.fields import SceneError

__all__ = ["fit_command"]


def _print_fit(console: Console, d: dict, errors: Console | None = None) -> None:
    """The fit's summary on ``console`` (stdout in the CLI); its warnings on ``errors`` (stderr)."""
    from vlab.identify.field_truth import summary_lines
    from vlab.identify.report import percent

    # Text, not markup: the CLI's console prints verbatim (a name or reason may hold "[...]")
    console.print(Text.assemble((d['name'], "bold"), f": {d['model']['name']} "
                  f"({'converged' if d['converged'] else 'NOT converged: ' + str(d['reason'])})"), highlight=False)
    said = None
    for k, u in d["uncertainty"].items():
        spread = f"± {u['standard_error']:.3g}" if u["interval"] is not None else \
            "(no interval: as above)" if u["reason"] == said else f"(no interval: {u['reason']})"
        said = u["reason"]
        console.print(f"  {k:>10} = {u['value']:.6g} {spread}", highlight=False, soft_wrap=True)
    for x in d["datasets"]:
        strain = (f"; strain rms {x['strain_rms']:.3g} against the DIC's noise {x['strain_noise']:.3g}"
                  if x["kind"] == "field" else "")  # the relative errors of a field fit are its force's
        console.print(f"  {x['name']} ({x['kind']}, {x['role']}): {'force ' if strain else ''}rms "
                      f"{percent(x['rms_relative'])}, max {percent(x['max_relative'])}{strain}", highlight=False)
        for line in summary_lines(x.get("end_to_end")):
            console.print(f"    {line}", highlight=False, soft_wrap=True)
    _print_specimens(console, d.get("specimens"))
    for w in d["warnings"]:
        (errors or console).print(Text.assemble("  ", ("warning", "yellow"), f" {w}"), highlight=False,
                                  soft_wrap=True)
    if d["converged"] and not d["trust"]["trustworthy"]:
        console.print(Text.assemble(("card not trustworthy", "red"), ": " + "; ".join(d["trust"]["because"])),
                      highlight=False, soft_wrap=True)


def _number(v, f: str = ".4g") -> str:
    return "—" if v is None else format(v, f)


def _print_specimens(console: Console, sp: dict | None) -> None:
    """fit.json → specimens as the page shows it: each specimen's constants, then per constant the
    mean, standard deviation, cv and n between specimens beside the pooled value (the card's)."""
    if not sp:
        return
    if sp["statistics"] is None:
        console.print(f"  specimens: n = {sp['n']} ({sp['reason']})", highlight=False, soft_wrap=True)
        return
    console.print(f"  specimens: n = {sp['n']} ({', '.join(sp['ids'])}), each fitted on its own; the pooled fit "
                  "above is the card", highlight=False, soft_wrap=True)
    for s, r in sp["per_specimen"].items():
        vals = ", ".join(f"{k} = {c['value']:.4g}" + (f" ± {c['standard_error']:.2g}" if c["interval"] else "")
                         for k, c in r["constants"].items())
        state = "" if r["converged"] else "  NOT converged"
        console.print(f"    {s}: {vals}{state}", highlight=False, soft_wrap=True)
    for k, st in sp["statistics"].items():
        g = _number
        cv = "—" if st["coefficient_of_variation"] is None else f"{100 * st['coefficient_of_variation']:.3g} %"
        why = f" ({st['reason']})" if st["reason"] else ""
        console.print(f"    {k:>10}: mean {g(st['mean'])}, sd {g(st['standard_deviation'], '.3g')}, cv {cv}, "
                      f"n {st['n']}; pooled {g(st['pooled'])}{why}", highlight=False, soft_wrap=True)


def _print_ranking(console: Console, rows: list[dict]) -> None:
    def pct(v):
        return "—" if v is None else f"{100 * v:.3g} %"
    console.print("  trustworthy cards first, each group ranked on the worse of the fit and held-out rms errors "
                  "(then BIC)", highlight=False)
    for r in rows:
        flags = ("" if r["converged"] else "  NOT converged") + \
            ("" if r["stable_over_fitted_ranges"] else "  unstable in the data ranges") + \
            ("" if r["trustworthy"] else "  not trustworthy")
        console.print(f"  {r['rank']}. {r['model']:<14} fit rms {pct(r['fit_rms_relative']):>8}  held-out rms "
                      f"{pct(r['held_out_rms_relative']):>8}  BIC {r['BIC']:.4g}{flags}", highlight=False, soft_wrap=True)


def exit_code(d: dict) -> int:
    """0 converged and trustworthy, 1 not converged, 3 converged but not trustworthy."""
    if not d["converged"]:
        return EXIT_FAILED
    return EXIT_OK if d["trust"]["trustworthy"] else EXIT_UNTRUSTED


def _destination(out: Path, force: bool, spec, path: Path):
    """The checked report folder: never one holding the fit file, its data or a cache."""
    from vlab.report.folder import Destination, check_destination
    from vlab.study.cache import DEFAULT_CACHE

    protect = [Path(path), DEFAULT_CACHE] + [Path(d.file) for d in spec.datasets]
    if spec.fe is not None:
        protect += [Path(spec.fe["scene_path"])] + ([Path(spec.fe["cache"])] if spec.fe.get("cache") else [])
    return check_destination(Destination(out, force=force, protect=tuple(protect)))


def fit_command(path: Path, out: Path | None, models: str | None, console: Console, force: bool = False,
                execution=None, export: str | None = None, results: Console | None = None) -> int:
    """Errors and warnings go to ``console`` (stderr in the CLI), the summary, ranking and the
    report's path to ``results`` (stdout; default ``console``). ``execution`` (vlab.study.sweep.Execution, from --workers/--scheduler): the FE-in-the-loop
    solves on Dask; refused (exit 2) for a fit without a specimen data set. ``export``: solvers
    (--export) whose cards go to OUT/cards/ (vlab.export), checked before the fit starts."""
    from vlab.identify.request import fit_request
    from vlab.report.folder import ReportFolderError
    from vlab.study.scheduler import SchedulerError

    try:
        request = fit_request(path, models, export, distributed=execution is not None)
    except SceneError as exc:
        return _refused(console, "invalid fit file", exc)
    try:
        dest = _destination(out or Path("reports") / f"{request.spec.name}-fit", force, request.spec, path)
    except ReportFolderError as exc:
        return _refused(console, "invalid output folder", exc)
    try:
        return _fit_and_write(request, dest, dest.path, console, execution, results or console)
    except SchedulerError as exc:
        return _refused(console, "invalid option", exc)
    except ReportFolderError as exc:
        return _refused(console, "cannot write report", exc)


def _refused(console: Console, what: str, exc: Exception) -> int:
    """Print what was refused (red) and why; the exit code of invalid input (2)."""
    console.print(Text.assemble((what, "red"), f" {exc}"), highlight=False, soft_wrap=True)
    return 2


def _fit_and_write(request, dest, out: Path, console: Console, execution, results: Console) -> int:
    from vlab.identify.request import run_ranking, run_single

    if request.names:
        from vlab.identify.ranking import write_ranking

        rows = write_ranking(request.spec, run_ranking(request), dest, request.text)
        _print_ranking(results, rows)
        results.print(f"report: {out / 'index.html'}", highlight=False, soft_wrap=True)
        if not all(r["converged"] for r in rows):
            return EXIT_FAILED
        return EXIT_OK if rows[0]["trustworthy"] else EXIT_UNTRUSTED
    from vlab.identify.report import write_fit_report

    try:
        outcome = run_single(request, execution)
    except SceneError as exc:  # found while fitting (e.g. the scene's test does not cover the data)
        return _refused(console, "invalid fit file", exc)
    d = write_fit_report(outcome, dest, request.text)
    _print_fit(results, d, console)
    results.print(f"report: {out / 'index.html'}", highlight=False, soft_wrap=True)
    return exit_code(d)
