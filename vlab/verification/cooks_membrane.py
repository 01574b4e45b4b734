"""Cook's membrane: the standard test of volumetric locking under bending and shear.

A tapered panel, corners (0, 0), (48, 44), (48, 60), (0, 44) mm, one element (1 mm) thick,
clamped on the left edge (x = 0), loaded by a uniform vertical dead traction on the right edge
(x = 48) totalling 1 N (t = 1/16 N/mm²). u_z = 0 on every node makes the slab exactly plane
strain. Neo-Hookean with the volumetric–isochoric split (vlab.materials.split.SplitNeoHookean,
ψ = ½μ(J^(−2/3) I₁ − 3) + ¼κ(J² − 1 − 2 ln J)) for both formulations, μ = 0.4225 MPa.
The quantity of interest is the vertical displacement of the top right corner C = (48, 60).

Literature check (``plane_strain=False``): J-P. V. Pelteret and A. McBride, "The deal.II code
gallery: Quasi-static finite-strain compressible elasticity" (2016), doi:10.5281/zenodo.1228964,
tabulate the tip u_y for this energy, load and geometry at ν = 0.3 with Q1 and Q2 (14.33 mm at
Q2 64 × 64). Their code marks the ±z faces by testing the x coordinate of the face centre, so u_z
is in fact free there (a 1 mm slab with free faces, close to plane stress): vlab's displacement Q2
reproduces their table only with u_z free (14.22 / 14.30 / 14.32 mm at 4 / 8 / 16 elements per
edge, theirs 14.22 / 14.30 / 14.32). For the plane-strain study (u_z = 0) no published value with
this exact set-up was found; the reference there is this study's finest Q2/P1dc run.

This is a study, not a scene: the lab's grips prescribe displacements, Cook's membrane needs a
traction, so the load enters here as a dead external force, Π(u) = W(u) − f_extᵀu, minimised by
vlab's Newton solver with its energy line search.
"""

from __future__ import annotations

import dataclasses
import logging
import time
from dataclasses import dataclass

import numpy as np
import skfem

from vlab.fe.assembly import Partition
from vlab.fe.mixed import MixedHyperelasticBody
from vlab.fe.newton import NewtonOptions
from vlab.fe.problem import HyperelasticBody
from vlab.fe.space import DisplacementSpace
from vlab.materials.split import SplitNeoHookean
from vlab.moduli import from_pair
from vlab.verification.dead_load import ramp

log = logging.getLogger(__name__)

MU = 0.4225                      # MPa (422.5 kPa, the code gallery's shear modulus)
TRACTION = 1.0 / 16.0            # N/mm², 1 N over the 16 mm × 1 mm right edge
THICKNESS = 1.0                  # mm
# Pelteret & McBride (2016), ν = 0.3, u_z free: tip u_y (mm) by elements per edge
GALLERY_TIP_NU_03 = {1: {1: 5.15, 2: 8.72, 4: 12.02, 8: 13.61, 16: 14.13, 32: 14.28, 64: 14.32},
                     2: {1: 12.19, 2: 13.83, 4: 14.22, 8: 14.30, 16: 14.32, 32: 14.33, 64: 14.33}}
TIP = (48.0, 60.0)               # mm
# plane strain, ν = 0.4999: this study's finest Q2/P1dc run (16 × 16), tip u_y in mm (run_study())
REFERENCE_TIP_NU_4999 = 11.48


@dataclass(frozen=True)
class CookResult:
    """One solve: tip vertical displacement (mm) and what it cost."""

    nu: float
    formulation: str             # "displacement" | "mixed"
    order: int                   # 1 (Q1) or 2 (Q2)
    divisions: int               # elements per edge
    tip_uy: float | None         # None if the solve failed
    dofs: int
    iterations: int
    seconds: float
    failure: str = ""
    per_step: list[int] = dataclasses.field(default_factory=list)  # Newton iterations per load step

    @property
    def element(self) -> str:
        pair = {(1, "mixed"): "Q1/P0", (2, "mixed"): "Q2/P1dc"}
        return pair.get((self.order, self.formulation), f"Q{self.order}")

    def as_dict(self) -> dict:
        return dataclasses.asdict(self) | {"element": self.element}


def membrane_mesh(divisions: int) -> skfem.MeshHex:
    """divisions × divisions × 1 hexes on the tapered panel (bilinear map of a rectangle)."""
    x = np.linspace(0.0, 48.0, divisions + 1)
    s = np.linspace(0.0, 1.0, divisions + 1)
    mesh = skfem.MeshHex.init_tensor(x, s, np.array([0.0, THICKNESS]))
    X, S, Z = mesh.p
    lower, upper = 44.0 / 48.0 * X, 44.0 + 16.0 / 48.0 * X
    return skfem.MeshHex(np.array([X, (1.0 - S) * lower + S * upper, Z]), mesh.t)


def edge_traction(space: DisplacementSpace, traction: float) -> np.ndarray:
    """Consistent nodal forces of a uniform y-traction on the face x = 48, N (vector DOFs)."""
    mesh = space.basis.mesh
    facets = mesh.facets_satisfying(lambda X: np.isclose(X[0], 48.0))
    face = skfem.FacetBasis(mesh, space.basis.elem, facets=facets, intorder=4)
    weights = skfem.asm(skfem.LinearForm(lambda v, w: traction * v), face)
    f = np.zeros(space.n_dofs)
    f[1::3] = weights
    return f


@dataclass(frozen=True)
class CookCase:
    nu: float
    formulation: str = "mixed"   # "displacement" | "mixed"
    order: int = 2               # 1: Q1 (Q1/P0 mixed), 2: Q2 (Q2/P1dc mixed)
    divisions: int = 4           # elements per edge
    plane_strain: bool = True    # u_z = 0 on every node; False: free faces (the code gallery's set-up)
    steps: int = 5               # equal load increments (halved on a Newton failure)
    mu: float = MU               # MPa
    traction: float = TRACTION   # N/mm² on the right edge
    three_field: bool = True     # mixed: Newton carries θ (False: θ projected at every iterate)
    kernel: str = "auto"         # mixed: "auto" (compiled where numba is available) | "numpy"


# de Souza Neto, Perić & Owen, Computational Methods for Plasticity (2008), Cook's membrane: G = 80.194 MPa,
# ν = 0.4999, 100 N over the 16 mm edge (6.25 N/mm²), plane strain; converged tip u_y 6.934 mm (issue 20)
SOUZA_NETO = dict(nu=0.4999, mu=80.194, traction=6.25, steps=10)


def solve_cook(case: CookCase, options: NewtonOptions = NewtonOptions(rtol=1e-9, max_iterations=30),
               ) -> CookResult:
    """One Cook's membrane solve; returns the tip displacement or the cause of failure."""
    t0 = time.perf_counter()
    nu, formulation, order, divisions = case.nu, case.formulation, case.order, case.divisions
    moduli = from_pair({"mu": case.mu, "nu": nu})
    law = SplitNeoHookean(moduli.lmbda, moduli.mu)
    space = DisplacementSpace.build(membrane_mesh(divisions), order)
    body = (MixedHyperelasticBody(space, law, case.three_field, case.kernel) if formulation == "mixed"
            else HyperelasticBody(space, law))
    X = space.node_coordinates
    clamped = np.flatnonzero(np.isclose(X[:, 0], 0.0))
    fixed = [3 * clamped[:, None] + np.arange(3)]
    if case.plane_strain:
        fixed.append(3 * np.arange(len(X)) + 2)
    prescribed = np.unique(np.concatenate([f.ravel() for f in fixed]))
    partition = Partition.build(body.pattern, prescribed)
    tip = np.flatnonzero(np.hypot(X[:, 0] - TIP[0], X[:, 1] - TIP[1]) < 1e-9)
    run = ramp(body, partition, edge_traction(space, case.traction), case.steps, options, 48.0)
    tip_uy = None if run.failure else float(np.mean(run.u[3 * tip + 1]))
    result = CookResult(nu, formulation, order, divisions, tip_uy, int(space.n_dofs), run.iterations,
                        time.perf_counter() - t0, run.failure, run.per_step)
    log.info("Cook nu=%g %s %d×%d: tip u_y = %s mm (%d DOFs, %d iterations, %.1f s)",
             nu, result.element, divisions, divisions, tip_uy, space.n_dofs, run.iterations, result.seconds)
    return result


@dataclass(frozen=True)
class StudyPlan:
    """Which series to run (plane strain): every formulation at each ν, levels per element order."""

    nus: tuple[float, ...] = (0.3, 0.4999)
    formulations: tuple[str, ...] = ("displacement", "mixed")
    levels: tuple[tuple[int, tuple[int, ...]], ...] = ((1, (2, 4, 8, 16, 32)), (2, (2, 4, 8, 16)))


def run_study(plan: StudyPlan = StudyPlan()) -> list[CookResult]:
    return [solve_cook(CookCase(nu, formulation, order, n))
            for nu in plan.nus for order, levels in plan.levels for formulation in plan.formulations
            for n in levels]


def reference_tip(results: list[CookResult], nu: float) -> tuple[float, str]:
    """(reference tip u_y, its source) for ν: the finest plane-strain Q2/P1dc run of the study."""
    finest = max((r for r in results if r.nu == nu and r.element == "Q2/P1dc" and r.tip_uy is not None),
                 key=lambda r: r.divisions)
    return finest.tip_uy, f"this study's finest Q2/P1dc run ({finest.divisions}×{finest.divisions})"


def table(results: list[CookResult]) -> str:
    """Markdown table: tip u_y per level, one column per (ν, element), with the reference row."""
    keys = sorted({(r.nu, r.formulation, r.order) for r in results}, key=lambda k: (k[0], k[2], k[1]))
    levels = sorted({r.divisions for r in results})
    by = {(r.nu, r.formulation, r.order, r.divisions): r for r in results}
    names = [f"ν={nu:g} {CookResult(nu, f, o, 0, None, 0, 0, 0).element} {'mixed' if f == 'mixed' else 'displ.'}"
             for nu, f, o in keys]
    lines = ["| elements per edge | " + " | ".join(names) + " |", "|---" * (len(keys) + 1) + "|"]
    for n in levels:
        cells = []
        for nu, f, o in keys:
            r = by.get((nu, f, o, n))
            cells.append("—" if r is None else "failed" if r.tip_uy is None else f"{r.tip_uy:.3f}")
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    refs = [reference_tip(results, nu)[0] for nu, _, _ in keys]
    lines.append("| reference | " + " | ".join(f"{v:.3f}" for v in refs) + " |")
    return "\n".join(lines)


def plot(results: list[CookResult], path) -> None:
    """Tip u_y against elements per edge, one panel per ν, reference dashed."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    nus = sorted({r.nu for r in results})
    fig, axes = plt.subplots(1, len(nus), figsize=(5.5 * len(nus), 4.2), squeeze=False)
    for ax, nu in zip(axes[0], nus):
        ref, source = reference_tip(results, nu)
        for formulation, order in sorted({(r.formulation, r.order) for r in results if r.nu == nu}):
            rows = sorted((r for r in results if (r.nu, r.formulation, r.order) == (nu, formulation, order)
                           and r.tip_uy is not None), key=lambda r: r.divisions)
            style = "-o" if formulation == "mixed" else "--s"
            label = f"{rows[0].element} ({formulation})" if rows else formulation
            ax.plot([r.divisions for r in rows], [r.tip_uy for r in rows], style, label=label)
        ax.axhline(ref, color="k", lw=0.8, ls=":", label=f"reference {ref:.2f} mm")
        ax.set_xscale("log", base=2)
        ax.set_xlabel("elements per edge")
        ax.set_ylabel("tip vertical displacement u_y(48, 60), mm")
        ax.set_title(f"Cook's membrane, plane strain, Neo-Hookean, ν = {nu:g}\nref: {source}", fontsize=9)
        ax.set_ylim(0.0, 1.15 * ref)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(out: str = "reports/cooks-membrane") -> None:  # pragma: no cover - the long study
    import json
    from pathlib import Path

    from vlab.report.folder import check_destination, report_folder

    logging.basicConfig(level=logging.INFO, format="%(message)s")
    check_destination(Path(out))  # refuse a folder vlab did not make before the long study
    results = run_study()
    with report_folder(Path(out), "cooks-membrane") as folder:  # the one writer of report folders
        (folder / "results.json").write_text(json.dumps([r.as_dict() for r in results], indent=1))
        (folder / "table.md").write_text(table(results) + "\n")
        plot(results, folder / "cooks_membrane.png")
    log.info("%s", table(results))


if __name__ == "__main__":  # pragma: no cover
    main()
