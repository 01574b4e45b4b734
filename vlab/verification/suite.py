"""The stability suite: a registry of hard cases, each with what it must show and what it got.

A case is a name, the expectation in words, a ``fast`` flag (the fast subset also runs in the
normal tests) and a function ``(CaseContext) -> Outcome``. Cases register themselves with
:func:`register`; :mod:`vlab.verification.cases` holds the built-in ones and any module may add more:

    from vlab.verification.suite import Outcome, register

    @register("cook-membrane-mixed", "tip displacement within 1 % of 16.4 mm", fast=False)
    def _(context):
        ...
        return Outcome(got=f"{tip:.4g} mm", passed=abs(tip / 16.4 - 1) < 0.01, converged=True,
                       iterations=..., details={...})

The runner times each case (wall clock) and turns an exception into a failed case with its
message, so one broken case never hides the others.
"""

from __future__ import annotations

import logging
import time
import traceback
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class CaseContext:
    """Where a case may write figures (None: write nothing) and whether it may render."""

    out: Path | None = None
    render: bool = True


@dataclass(frozen=True)
class Outcome:
    """What a case got. ``negative_eigenvalues``: the most found at any vetted state (None if
    the case has no stability record); ``details``: numbers for results.json; ``figures``: files
    written into the context's folder."""

    got: str
    passed: bool
    converged: bool
    iterations: int = 0
    cutbacks: int = 0
    negative_eigenvalues: int | None = None
    details: dict = field(default_factory=dict)
    figures: list[str] = field(default_factory=list)


@dataclass(frozen=True)
class Case:
    name: str
    expected: str
    run: Callable[[CaseContext], Outcome]
    fast: bool = True


@dataclass(frozen=True)
class CaseResult:
    name: str
    expected: str
    fast: bool
    outcome: Outcome
    seconds: float

    @property
    def passed(self) -> bool:
        return self.outcome.passed

    def as_dict(self) -> dict:
        return {"name": self.name, "expected": self.expected, "fast": self.fast,
                "seconds": self.seconds, **asdict(self.outcome)}


CASES: dict[str, Case] = {}


def register(name: str, expected: str, fast: bool = True):
    """Decorator adding ``function(context) -> Outcome`` to the suite under ``name``."""
    def add(function: Callable[[CaseContext], Outcome]):
        if name in CASES:
            raise ValueError(f"stability case {name!r} is registered twice")
        CASES[name] = Case(name, expected, function, fast)
        return function
    return add


def select(fast_only: bool = False, names: list[str] | None = None) -> list[Case]:
    """The registered cases (built-ins loaded), the fast subset or those named."""
    import vlab.verification.cases  # noqa: F401  (registers the built-in cases)
    import vlab.verification.incompressible  # noqa: F401  (locking, ν = ½, the ν = 0.499 dogbone)
    import vlab.verification.new_kinds  # noqa: F401  (torsion past a surface shear of 1, the die to 0.7)

    if names:
        unknown = [n for n in names if n not in CASES]
        if unknown:
            raise KeyError(f"unknown stability case(s) {', '.join(unknown)}; known: {', '.join(CASES)}")
        return [CASES[n] for n in names]
    return [c for c in CASES.values() if c.fast or not fast_only]


def run_case(case: Case, context: CaseContext) -> CaseResult:
    start = time.perf_counter()
    try:
        outcome = case.run(context)
    except Exception as exc:  # a broken case is a failed case, reported with its cause
        log.error("stability case %s raised: %s", case.name, traceback.format_exc())
        outcome = Outcome(got=f"error: {type(exc).__name__}: {exc}", passed=False, converged=False)
    return CaseResult(case.name, case.expected, case.fast, outcome, time.perf_counter() - start)


def run_suite(cases: list[Case], context: CaseContext,
              progress: Callable[[CaseResult], None] | None = None) -> list[CaseResult]:
    results = []
    for case in cases:
        result = run_case(case, context)
        results.append(result)
        if progress is not None:
            progress(result)
    return results


def suite_mode(fast_only: bool, names: list[str] | None) -> str:
    """results.json's "mode": "selected" (cases named), "fast" (the fast subset) or "full"."""
    return "selected" if names else "fast" if fast_only else "full"


def run_timed(cases: list[Case], context: CaseContext,
              progress: Callable[[CaseResult], None] | None = None) -> tuple[list[CaseResult], float]:
    """The cases' results and the suite's wall time (s)."""
    start = time.perf_counter()
    results = run_suite(cases, context, progress)
    return results, time.perf_counter() - start
