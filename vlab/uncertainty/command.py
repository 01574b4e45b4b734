"""`vlab budget SCENE`: validate, run the paired runs and the samples as sweeps, write, print.

Exit 0; 1 when some samples failed (the budget is of the others, and says how many) or the
nominal run failed (nothing written); 2 on invalid input (nothing written).
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

__all__ = ["budget_command"]


def _spec(parsed, samples: Optional[int]):
    import dataclasses

    from vlab.cli_io import fail
    from vlab.fields import SceneError
    from vlab.uncertainty.spec import parse_uncertainty

    try:
        spec = parse_uncertainty(parsed.source.get("uncertainty", {}), parsed)
    except SceneError as exc:
        fail("invalid scene", exc)
    if samples is not None:
        if not 1 <= samples <= 100000:
            fail("invalid option", f"--samples {samples}: must be 1..100000")
        spec = dataclasses.replace(spec, samples=samples)
    if not spec.sources:
        fail("invalid scene", "[uncertainty] leaves no input uncertain (every tolerance 0, both classes \"none\", "
                              "no material scatter): there is nothing to budget")
    return spec


def _print(budget: dict, index: Path) -> None:
    """The budget's results on stdout (the sweeps' progress bars are on stderr)."""
    from vlab.cli_io import show

    for name, label in (("E", "E"), ("nu", "nu"), ("E_crosshead", "E (crosshead)")):
        q = budget.get(name)
        if q is None:
            continue
        show(f"{label} = {q['mean']:.6g} ± {q['U']:.3g} (k = 2, Monte Carlo of {q['samples']}; GUM U = "
             f"{q['gum']['U']:.3g})")
        for r in q["contributions"][:4]:
            share = "—" if r["share"] is None else f"{100 * r['share']:.3g} %"
            sob = "—" if r["sobol"] is None else f"{r['sobol']:.2f}"
            show(f"  {r['input']:<36} share {share:>8}  Sobol {sob}")
    show(f"{budget['runs']['paired'] + budget['runs']['samples']} runs ({budget['runs']['cache_hits']} cached, "
         f"{budget['runs']['computed']} computed, {budget['failed_samples']} samples failed); report: {index}")
    pb = budget.get("percent_bending")
    if pb:
        g = {k: "—" if pb[k] is None else f"{pb[k]:.3g}" for k in ("nominal", "mean", "u", "max_abs")}
        show(f"ASTM E1012 percent bending at the gauge centre: nominal {g['nominal']} %, samples {g['mean']} ± "
             f"{g['u']} % (largest {g['max_abs']} %)")


def budget_command(scene: Path, samples: Optional[int], workers: Optional[int], scheduler: Optional[str], out: Optional[Path],
                   cache: Path, quiet: bool, force: bool) -> int:
    import typer

    from vlab.cli import _execution, _load, _sweep_with_progress, _write
    from vlab.cli_io import EXIT_FAILED, EXIT_OK, cache_folder, fail, report_destination
    from vlab.study.summary import RunKnobs
    from vlab.uncertainty.budget import BudgetError, compute_budget
    from vlab.uncertainty.report import write_budget

    parsed, text = _load(scene)
    execution = _execution(workers, scheduler)
    spec = _spec(parsed, samples)
    cache = cache_folder(cache)
    dest = report_destination(out or Path("reports") / f"{parsed.name}-budget", force, scene, [cache])

    def runner(points, what):
        return _sweep_with_progress(points, RunKnobs(), cache, execution, quiet, what)

    try:
        budget, runs = compute_budget(parsed.source, spec, Path(scene).parent, runner,
                                      parsed.measure.modulus_window[0])
    except BudgetError as exc:
        fail("budget failed", exc, EXIT_FAILED)
    budget = {"scene": parsed.name} | budget
    index = _write(write_budget, dest, budget, spec, runs, text)
    _print(budget, index)
    raise typer.Exit(EXIT_FAILED if budget["failed_samples"] else EXIT_OK)
