"""Near-incompressibility cases of ``vlab stability`` (issue 5): volumetric locking shows, the mixed
formulation cures it, and ν = ½ is refused.

* Cook's membrane (plane strain, Neo-Hookean with the volumetric–isochoric split, ν = 0.4999): the
  tip displacement u_y(48, 60) of the displacement Q1 hexes stalls far below the reference while
  the mixed Q1/P0 and Q2/P1dc converge towards it. The reference, 11.48 mm, is the finest
  Q2/P1dc run (16 × 16) of vlab.verification.cooks_membrane's convergence study.
* ν = 0.5 exactly: an infinite bulk modulus κ = E / (3(1 − 2ν)); refused when the scene is read,
  with the message pointing to the mixed formulation's verified limit ν ≤ 0.4999.
* ISO 527-2 1BA dogbone at ν = 0.499 between clamped grips: the extensometers recover ν within
  1 % with the mixed formulation; the displacement formulation's error (locked by the grips) is
  reported beside it.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from vlab.moduli import MIXED_NU_LIMIT, ModuliError, from_pair
from vlab.report.results import result_to_dict
from vlab.run import run_scene
from vlab.scene import SceneError, apply_overrides, parse_scene
from vlab.verification.suite import CaseContext, Outcome, register
from vlab.verification.cooks_membrane import MU, REFERENCE_TIP_NU_4999, CookCase, CookResult, solve_cook

NU = 0.4999
STALLED = 0.45      # locked: the displacement Q1 tip stays below 45 % of the reference
DOGBONE = Path(__file__).resolve().parents[2] / "specimens" / "dogbone-iso527-2-1ba.toml"


def _cook_series(levels: dict[tuple[str, int], tuple[int, ...]]) -> dict[str, list[CookResult]]:
    """Tip displacements at ν = 0.4999 by element ("Q1", "Q1/P0", "Q2/P1dc"), coarse to fine."""
    series: dict[str, list[CookResult]] = {}
    for (formulation, order), divisions in levels.items():
        runs = [solve_cook(CookCase(NU, formulation, order, n)) for n in divisions]
        series[runs[0].element] = runs
    return series


def _cook_outcome(series: dict[str, list[CookResult]], passed_if) -> Outcome:
    """Outcome listing every tip (mm, % of the reference); ``passed_if(tips by element)``."""
    ref = REFERENCE_TIP_NU_4999
    failed = [f"{r.element} {r.divisions}×{r.divisions}: {r.failure}"
              for runs in series.values() for r in runs if r.tip_uy is None]
    tips = {element: [r.tip_uy for r in runs] for element, runs in series.items()}
    parts = [f"{element} " + " → ".join(f"{r.tip_uy:.2f}" if r.tip_uy is not None else "failed" for r in runs)
             + f" ({', '.join(str(r.divisions) for r in runs)} per edge)" for element, runs in series.items()]
    got = "; ".join(parts) + f" mm; ref {ref:.2f} mm"
    runs = [r for rs in series.values() for r in rs]
    details = {"reference_tip_mm": ref, "failures": failed,
               "runs": [r.as_dict() | {"ratio_to_reference": r.tip_uy and r.tip_uy / ref} for r in runs]}
    return Outcome(got=got, passed=not failed and bool(passed_if(tips)), converged=not failed,
                   iterations=sum(r.iterations for r in runs), details=details)


@register("cook-membrane-0.4999-coarse",
          f"ν = 0.4999, tip u_y vs ref {REFERENCE_TIP_NU_4999} mm: displacement Q1 stalls below "
          f"{STALLED:.0%} (2→4 per edge gains < 5 %); Q1/P0 rises above 80 %; Q2/P1dc 2×2 within 2 %")
def cook_coarse(context: CaseContext) -> Outcome:
    series = _cook_series({("displacement", 1): (2, 4), ("mixed", 1): (2, 4), ("mixed", 2): (2,)})
    ref = REFERENCE_TIP_NU_4999

    def passed(tips):
        q1, q1p0, q2p1 = tips["Q1"], tips["Q1/P0"], tips["Q2/P1dc"]
        return (max(q1) < STALLED * ref and q1[1] - q1[0] < 0.05 * ref
                and q1p0[1] > q1p0[0] and q1p0[1] > 0.8 * ref and abs(q2p1[0] / ref - 1) < 0.02)
    return _cook_outcome(series, passed)


@register("cook-membrane-0.4999-fine",
          f"ν = 0.4999, finer levels: displacement Q1 still below {STALLED:.0%} of ref "
          f"{REFERENCE_TIP_NU_4999} mm at 16×16; Q1/P0 16×16 within 2 %; Q2/P1dc 8×8 within 0.5 %",
          fast=False)
def cook_fine(context: CaseContext) -> Outcome:
    series = _cook_series({("displacement", 1): (8, 16), ("mixed", 1): (8, 16), ("mixed", 2): (4, 8)})
    ref = REFERENCE_TIP_NU_4999

    def passed(tips):
        return (max(tips["Q1"]) < STALLED * ref and abs(tips["Q1/P0"][-1] / ref - 1) < 0.02
                and abs(tips["Q2/P1dc"][-1] / ref - 1) < 0.005)
    return _cook_outcome(series, passed)


def _block_scene(nu: float, formulation: str) -> dict:
    return {"name": "nu-half", "specimen": {"shape": "block", "size": [10.0, 10.0, 10.0]},
            "mesh": {"size": 10.0, "cell": "hex", "formulation": formulation},
            "material": {"model": "neo-hookean", "E": 10.0, "nu": nu},
            "test": {"kind": "uniaxial", "stretch": 1.1, "steps": 1}}


@register("nu-0.5-refused",
          f"ν = 0.5 refused when read (scene, both formulations, and the moduli of a study), naming "
          f"material.nu and the mixed formulation's limit ν ≤ {MIXED_NU_LIMIT:g}; ν = {MIXED_NU_LIMIT:g} accepted")
def nu_half_refused(context: CaseContext) -> Outcome:
    messages = []
    for formulation in ("mixed", "displacement"):
        try:
            parse_scene(_block_scene(0.5, formulation))
            messages.append(None)
        except SceneError as exc:
            messages.append(str(exc))
    try:
        from_pair({"mu": MU, "nu": 0.5})
        messages.append(None)
    except ModuliError as exc:
        messages.append(str(exc))
    limit_ok = parse_scene(_block_scene(MIXED_NU_LIMIT, "mixed")).material is not None

    def points_to_the_limit(message):
        return (message is not None and "material.nu" in message and f"{MIXED_NU_LIMIT:g}" in message
                and "mixed" in message)
    passed = all(points_to_the_limit(m) for m in messages) and limit_ok
    first = messages[0] or "accepted (no error)"
    pointer = first[first.find("for a nearly"):] if "for a nearly" in first else first[-150:]
    return Outcome(got=f"refused ×{sum(m is not None for m in messages)}/3 (material.nu): …{pointer}",
                   passed=passed, converged=False, details={"messages": messages, "limit_accepted": limit_ok})


def _dogbone(formulation: str):
    raw = tomllib.loads(DOGBONE.read_text())
    scene = parse_scene(apply_overrides(raw, {
        "material.model": "neo-hookean", "material.E": 10.0, "material.nu": 0.499, "mesh.cell": "hex",
        "mesh.formulation": formulation, "test.stretch": 1.0002, "test.steps": 1,
        "measure.modulus_window": [1e-5, 5e-5]}), origin=DOGBONE.name)
    result = run_scene(scene)
    return result, result_to_dict(result)


@register("dogbone-1ba-nu-0.499-mixed",
          "ISO 527-2 1BA, Neo-Hookean ν = 0.499, clamped grips: the mixed formulation recovers ν (and E) "
          "within 1 %; the displacement formulation's error is shown beside it")
def dogbone_nu_0499(context: CaseContext) -> Outcome:
    errors, iterations, converged = {}, 0, True
    for formulation in ("mixed", "displacement"):
        result, data = _dogbone(formulation)
        converged &= bool(data["converged"])
        iterations += int(sum(data["solver"]["newton_iterations"]))
        c = result.constants if result.converged else None
        errors[formulation] = None if c is None else {"E": c.E / 10.0 - 1, "nu": c.nu / 0.499 - 1}

    def show(e):
        return "failed" if e is None else f"ν {e['nu']:+.2%}, E {e['E']:+.2%}"
    mixed = errors["mixed"]
    passed = converged and mixed is not None and abs(mixed["nu"]) < 0.01 and abs(mixed["E"]) < 0.01
    return Outcome(got=f"mixed: {show(mixed)}; displacement: {show(errors['displacement'])}", passed=passed,
                   converged=converged, iterations=iterations, details={"relative_errors": errors})
