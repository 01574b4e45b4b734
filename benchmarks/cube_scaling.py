"""Cube scaling (issue #20): vlab, FElupe + PARDISO and a plain CG + AMG Newton, side by side.

    nice -n 10 python benchmarks/cube_scaling.py [--sizes 8,16,24,32] [--codes vlab,felupe,amg]
                                                 [--felupe-max 32] [--out benchmarks/RESULTS.md]

Problem (benchmarks/run.py): a Neo-Hookean cube (E = 10 MPa, ν = 0.3) of n × n × n mm, Q1
hexahedra of 1 mm, stretched to 1.5 in 10 equal steps between roller grips, ‖r_free‖ /
‖r_prescribed‖ ≤ 1e-8. Every run is its own subprocess (peak RSS = ru_maxrss of that run).

- vlab: ``run_scene`` with the defaults (``solver.linear = "auto"``: PARDISO below 50,000 free
  DOFs, CG + AMG with the LOBPCG stability check above); its per-phase times and peak memory are
  the run's own (results.json ``timing``).
- FElupe + PARDISO: benchmarks/run.py's ``run_felupe`` (same nodes and elements).
- CG + AMG reference: written here, no vlab solver logic: vlab's body assembles the very same
  K and f_int; plain Newton as FElupe runs it (the first iteration of a step applies the grips'
  increment through the last state's tangent, K_ff Δu_f = −r_f − K_fp Δu_p; no extrapolation, no
  line search, no reuse), each iteration a fresh pyamg smoothed-aggregation set-up (rigid-body
  near-nullspace) and pyamg's CG to a relative residual of 1e-6. No stability check (it only
  solves).

The growth exponent is the least-squares slope of log(time) against log(DOFs) from 24³ up.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import vlab  # noqa: E402  before numpy: numpy's BLAS serial, as in the CLI

vlab.serial_blas_process()
import numpy as np  # noqa: E402

import run as bench  # noqa: E402  benchmarks/run.py: the scene, FElupe's set-up

REFERENCE_CG_RTOL = 1e-6
BEGIN, END = "<!-- cube-scaling -->", "<!-- /cube-scaling -->"


def _problem(n: int) -> str:
    name = f"cube{n}"
    bench.PROBLEMS[name] = ("hex", 1, float(n), 1.0)
    return name


def run_vlab(n: int) -> dict:
    from vlab import jit, settings
    from vlab.fe import linsolve
    from vlab.report.results import result_to_dict
    from vlab.run import run_scene

    scene = bench._scene(_problem(n))
    linsolve.solver_in_use()
    jit.available(settings.current())
    t0 = time.perf_counter()
    result = run_scene(scene)
    total = time.perf_counter() - t0
    if not result.converged:
        return {"error": result.history.failure.reason}
    data = result_to_dict(result)
    timing, linear = data["timing"], data["solver"]["linear"]
    return {"dofs": int(result.space.n_dofs), "total": total,
            "iterations": int(sum(data["solver"]["newton_iterations"])),
            "factorizations": int(linear["factorizations"]), "amg_setups": int(linear["amg_setups"]),
            "path": linear["newton"], "stability": linear["stability_methods"],
            "assembly": timing["assembly_s"], "linear": timing["linear_solve_s"],
            "stability_s": timing.get("stability_check_s", 0.0), "phase_peak_mb": timing["peak_memory_mb"],
            "force": float(result.curve.force[0][-1]), "peak_mb": bench._peak_mb()}


def run_amg_reference(n: int) -> dict:
    """Plain Newton with a fresh CG + AMG solve per iteration on vlab's assembled K (docstring)."""
    import pyamg

    from vlab.fe.iterative import rigid_body_modes
    from vlab.pipeline.prepare import prepare

    t0 = time.perf_counter()
    prepared = prepare(bench._scene(_problem(n)))
    body, part, u_hat = prepared.body, prepared.partition, prepared.loading.u_hat
    free, fixed = part.free, part.prescribed
    B = rigid_body_modes(body.space.node_coordinates)[free]
    u = np.zeros(body.space.n_dofs)
    seconds = {"assembly": 0.0, "setup": 0.0, "cg": 0.0}
    iterations = setups = 0
    ev = body.evaluate(u)
    for t in np.arange(1, bench.STEPS + 1) / bench.STEPS:
        jump = t * u_hat[fixed] - u[fixed]  # the grips' increment, applied by the first iteration
        for k in range(30):
            r = ev.f_int[free]
            if k > 0 and np.linalg.norm(r) <= bench.RTOL * max(np.linalg.norm(ev.f_int[fixed]), 1e-300):
                break
            a = time.perf_counter()
            Kff, Kfp = part.blocks(body.stiffness(ev))
            Kff = Kff.tocsr()
            b = time.perf_counter()
            ml = pyamg.smoothed_aggregation_solver(Kff, B=B, symmetry="symmetric")
            c = time.perf_counter()
            rhs = -r - (Kfp @ jump if k == 0 else 0.0)
            du, info = pyamg.krylov.cg(Kff, rhs, M=ml.aspreconditioner(), tol=REFERENCE_CG_RTOL, maxiter=500)
            seconds["assembly"] += b - a
            seconds["setup"] += c - b
            seconds["cg"] += time.perf_counter() - c
            u[free] += du
            if k == 0:
                u[fixed] += jump
            ev = body.evaluate(u)
            iterations, setups = iterations + 1, setups + 1
            if ev.f_int is None:
                return {"error": f"an element inverted at t = {t}"}
        else:
            return {"error": f"no convergence at t = {t}"}
    ev = body.evaluate(u)
    moving = prepared.loading.moving_dofs[0]
    return {"dofs": int(body.space.n_dofs), "total": time.perf_counter() - t0, "iterations": iterations,
            "factorizations": 0, "amg_setups": setups, **seconds,
            "force": float(ev.f_int[moving].sum()), "peak_mb": bench._peak_mb()}


def run_felupe(n: int) -> dict:
    out = bench.run_felupe(_problem(n))
    out["factorizations"] = out["iterations"]
    return out


CODES = {"vlab": run_vlab, "felupe": run_felupe, "amg": run_amg_reference}


def _child(code: str, n: int) -> dict:
    proc = subprocess.run([sys.executable, __file__, "--one", code, str(n)], capture_output=True,
                          text=True, cwd=ROOT)
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[7:])
    return {"error": (proc.stderr.strip().splitlines() or ["no output"])[-1]}


def exponent(rows: list[tuple[int, dict]], key: str = "total", first: int = 24) -> float | None:
    """Least-squares slope of log(time) against log(DOFs) over the sizes ≥ ``first``."""
    pts = [(r["dofs"], r[key]) for n, r in rows if n >= first and "error" not in r and key in r]
    if len(pts) < 2:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def _cell(r: dict, key: str, fmt: str = "{:.2f}") -> str:
    return fmt.format(r[key]) if key in r and r[key] is not None else "—"


def table(rows: list[tuple[int, str, dict]]) -> str:
    head = ("| cube | code | DOFs | Newton it. | factorizations | AMG set-ups | total s | assembly s "
            "| linear s | stability s | stability methods | peak MB | peak MB per phase | force N |")
    lines = [head, "|" + "---|" * 14]
    for n, code, r in rows:
        if "error" in r:
            lines.append(f"| {n}³ | {code} | | | | | | | | | | | {r['error'][:80]} | |")
            continue
        linear = r.get("linear", r["cg"] + r["setup"] if "cg" in r else None)
        phases = ", ".join(f"{k} {v:.0f}" for k, v in (r.get("phase_peak_mb") or {}).items())
        methods = ", ".join(f"{k} {v}" for k, v in (r.get("stability") or {}).items())
        lines.append(f"| {n}³ | {code} | {r['dofs']:,} | {r['iterations']} | {r.get('factorizations', '—')} "
                     f"| {r.get('amg_setups', 0)} | {r['total']:.2f} | {_cell(r, 'assembly')} | {_cell({'x': linear}, 'x')} "
                     f"| {_cell(r, 'stability_s')} | {methods or '—'} | {r['peak_mb']:.0f} | {phases or '—'} "
                     f"| {r['force']:.6g} |")
    return "\n".join(lines)


def summary(rows: list[tuple[int, str, dict]]) -> str:
    out = []
    for code in CODES:
        mine = [(n, r) for n, c, r in rows if c == code]
        slope = exponent(mine)
        if slope is not None:
            out.append(f"- {code}: time ∝ N^{slope:.2f} from 24³ up")
    by_size: dict[int, dict[str, dict]] = {}
    for n, code, r in rows:
        if "error" not in r:
            by_size.setdefault(n, {})[code] = r
    for n, codes in sorted(by_size.items()):
        if "vlab" in codes and len(codes) > 1:
            peers = {c: r["total"] for c, r in codes.items() if c != "vlab"}
            fastest = min(peers, key=peers.get)
            v = codes["vlab"]
            out.append(f"- {n}³: vlab / fastest peer ({fastest}) = {v['total'] / peers[fastest]:.2f}; "
                       f"vlab peak {v['peak_mb'] / (v['dofs'] / 1e5):.0f} MB per 100k DOFs")
    return "\n".join(out)


def write(out: Path, text: str) -> None:
    """Replace the cube-scaling section of ``out`` (between the markers), or append it."""
    old = out.read_text() if out.exists() else ""
    block = f"{BEGIN}\n{text}\n{END}"
    if BEGIN in old and END in old:
        new = old[:old.index(BEGIN)] + block + old[old.index(END) + len(END):]
    else:
        new = old.rstrip("\n") + "\n\n" + block + "\n"
    out.write_text(new)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--one", nargs=2, metavar=("CODE", "N"))
    ap.add_argument("--sizes", default="8,16,24,32")
    ap.add_argument("--codes", default="vlab,felupe,amg")
    ap.add_argument("--felupe-max", type=int, default=32, help="largest cube for FElupe (its direct solver's memory)")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    if args.one:
        print("RESULT " + json.dumps(CODES[args.one[0]](int(args.one[1]))))
        return
    rows = []
    for n in (int(s) for s in args.sizes.split(",")):
        for code in args.codes.split(","):
            if code == "felupe" and n > args.felupe_max:
                continue
            r = _child(code, n)
            rows.append((n, code, r))
            print(n, code, json.dumps(r), flush=True)
    command = "python benchmarks/cube_scaling.py " + " ".join(sys.argv[1:])
    text = (f"## Cube scaling (issue #20)\n\nCommand: `{command}`\n\nMachine: {bench._machine()}\n\n"
            + table(rows) + "\n\n" + summary(rows) + "\n")
    print(text)
    if args.out:
        write(args.out, text)


if __name__ == "__main__":
    main()
