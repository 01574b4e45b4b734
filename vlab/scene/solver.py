"""``[solver]``: Newton's relative residual tolerance (default 1e-8), iteration and cutback limits
(25, 8), eigenvalues at every level, the linear solver (auto | direct | cg-amg) and the Newton
variant (reuse | exact)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from vlab import fields
from vlab.fields import SceneError

__all__ = ["SolverSpec", "parse_solver"]


@dataclass(frozen=True)
class SolverSpec:
    rtol: float
    max_iterations: int
    max_cutbacks: int
    eigenvalues: bool = False  # lowest eigenvalue of K_ff at every converged state
    linear: str = "auto"  # Newton corrections: "auto" | "direct" | "cg-amg" (vlab.fe.iterative)
    newton: str = "reuse"  # "reuse": keep a factor while chord steps contract; "exact": refactorize


def parse_solver(raw: Any) -> SolverSpec:
    t = fields.Table("solver", raw, ("rtol", "max_iterations", "max_cutbacks", "eigenvalues", "linear", "newton"))
    eigenvalues = t.get("eigenvalues", False)
    if not isinstance(eigenvalues, bool):
        raise SceneError(f"{t.field('eigenvalues')} must be true or false, got {fields.show(eigenvalues)}")
    return SolverSpec(rtol=t.number("rtol", default=1e-8, ge=1e-14, le=1e-2),
                      max_iterations=t.integer("max_iterations", 1, 200, default=25),
                      max_cutbacks=t.integer("max_cutbacks", 0, 30, default=8), eigenvalues=eigenvalues,
                      linear=t.choice("linear", ("auto", "direct", "cg-amg"), default="auto"),
                      newton=t.choice("newton", ("reuse", "exact"), default="reuse"))
