"""Gmsh tetrahedra against vlab's split-hex tetrahedra on the ISO 527-2 1A dumb-bell: what accuracy
each buys per second, the cost study of the README ("Cost, sweeps and caching") made repeatable.

    python benchmarks/gmsh_tets.py            # prints both tables (minutes; times are noisy under load)
    python benchmarks/gmsh_tets.py --record   # ... and writes them, with the command, into benchmarks/RESULTS.md
    python benchmarks/gmsh_tets.py --coarse   # one coarse linear pair (seconds; tests/test_gmsh_tets_benchmark.py)

1. The cost study: `specimens/dogbone-iso527-2-1a.toml` (Neo-Hookean E = 10 MPa, ν = 0.3, clamped
   grips, stretch 1.5) at mesh.size 4, the mesh families `vlab cost SCENE --cells tet,gmsh-tet
   --orders 1,2 --levels 3 --ratio 1.414` builds (vlab: every structured hexahedron split into
   tetrahedra; Gmsh: `mesh.mesher = "gmsh"`, Delaunay tetrahedra of the same outline, smoothed by
   Netgen), run one after another in this process, each family level interleaved with the other
   mesher's. Errors against the study's own Richardson reference (vlab.study.cost.analyse, the
   code `vlab cost` runs).
2. The linear model (the same mesh pairs, stretch 1.01): its E and ν converge to the input, so
   their error is the discretisation's alone, with no reference to extrapolate.

DOFs, mesh quality and errors are deterministic; wall times are not (shared machine).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "specimens" / "dogbone-iso527-2-1a.toml"
RESULTS = Path(__file__).resolve().parent / "RESULTS.md"
BEGIN, END = "<!-- benchmarks/gmsh_tets.py: begin -->", "<!-- benchmarks/gmsh_tets.py: end -->"
MESHERS = {"tet": "vlab split hex", "gmsh-tet": "Gmsh"}
LINEAR = {"material.model": "linear", "test.stretch": 1.01, "test.steps": 2}


def scene(overrides: dict | None = None):
    import tomllib

    from vlab.scene import apply_overrides, parse_scene

    raw = tomllib.loads(SCENE.read_text(encoding="utf-8"))
    return parse_scene(apply_overrides(raw, overrides or {}), origin=SCENE.name, base_dir=SCENE.parent)


def mesh_points(base, orders=(1, 2), levels: int = 3, ratio: float = 1.414):
    """The mesh-size runs of the cost study (GridPoints), each level's vlab run next to Gmsh's."""
    from vlab.study.cost import CostOptions, knob_points

    options = CostOptions(levels=levels, ratio=ratio, orders=tuple(orders), cells=tuple(MESHERS))
    points = [p for p in knob_points(base, options) if p.label["knob"].startswith("mesh size")]
    return options, sorted(points, key=lambda p: (p.source["mesh"]["order"], -p.label["value"],
                                                  p.source["mesh"].get("mesher", "vlab")))


def mean_quality(source: dict) -> float:
    """Mean element quality (mean ratio of the tetrahedra) of the mesh a point builds."""
    from vlab.pipeline.prepare import build_specimen, checked_quality
    from vlab.scene import parse_scene

    s = parse_scene(source, origin=SCENE.name, base_dir=SCENE.parent)
    return checked_quality(s, build_specimen(s)).mean_quality


def run_points(points) -> list[dict]:
    """The study summary of every point (in order), with its mean mesh quality."""
    from vlab.study.summary import RunKnobs, summarize

    out = []
    for p in points:
        s = summarize(p.source, RunKnobs(), p.label, str(SCENE.parent))
        s["mean_quality"] = mean_quality(p.source) if s.get("status") == "ok" else None
        out.append(s)
        print(f"  {p.label['knob']} = {p.label['value']}: {s.get('status')} "
              f"({(s.get('timing') or {}).get('total_s', 0):.1f} s)", file=sys.stderr, flush=True)
    return out


def _family(summary: dict) -> tuple[str, int]:
    cell = summary["label"]["knob"].split(", ")[-1].rstrip(")")
    return MESHERS[cell], summary["mesh"]["order"]


def _pct(x) -> str:
    return "—" if x is None else f"{x:.2e}"


def cost_table(base, summaries: list[dict], options) -> str:
    """Markdown: the study's rows, errors against its Richardson reference."""
    from vlab.study.cost import analyse, run_seconds

    analysis = analyse(base, summaries, options)
    lines = ["| mesher | order | mesh.size | DOFs | mean quality | E error | ν error | force error | "
             "largest error | run s |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for s, e in zip(summaries, analysis.errors):
        mesher, order = _family(s)
        if e is None:
            lines.append(f"| {mesher} | {order} | {s['label']['value']:g} | — | — | {s.get('status')}: "
                         f"{s.get('diagnosis')} | | | | |")
            continue
        lines.append(f"| {mesher} | {order} | {s['label']['value']:g} | {s['mesh']['dofs']} | "
                     f"{s['mean_quality']:.2f} | {_pct(e['E'])} | {_pct(e['nu'])} | {_pct(e['final_force'])} | "
                     f"{_pct(e['max'])} | {run_seconds(s):.1f} |")
    ref = ", ".join(f"{q} {v:.8g}" for q, v in analysis.reference.items() if v is not None)
    orders = ", ".join(f"{q} {v:.2f}" for q, v in analysis.orders.items() if v is not None)
    lines += ["", f"Reference ({analysis.reference_kind}): {ref}; observed orders: {orders or '—'}.",
              f"Cheapest for the {options.target:.0%} target: {analysis.recommendation}"]
    return "\n".join(lines)


def linear_rows(orders=(1, 2), levels: int = 3, size: float = 4.0, ratio: float = 1.414) -> list[dict]:
    """The linear model on each mesh pair: E and ν against the input (the discretisation error)."""
    base = scene(LINEAR | {"mesh.size": size})
    _, points = mesh_points(base, orders, levels, ratio)
    rows = []
    for s in run_points(points):
        mesher, order = _family(s)
        m = s.get("measured") or {}
        rows.append({"mesher": mesher, "order": order, "size": s["label"]["value"], "status": s.get("status"),
                     "dofs": (s.get("mesh") or {}).get("dofs"), "quality": s["mean_quality"],
                     "E": m.get("E"), "nu": m.get("nu"), "run_s": (s.get("timing") or {}).get("total_s")})
    return rows


def linear_table(rows: list[dict]) -> str:
    lines = ["| mesher | order | mesh.size | DOFs | mean quality | E error | ν error | run s |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        if r["status"] != "ok":
            lines.append(f"| {r['mesher']} | {r['order']} | {r['size']:g} | — | — | {r['status']} | | |")
            continue
        lines.append(f"| {r['mesher']} | {r['order']} | {r['size']:g} | {r['dofs']} | {r['quality']:.2f} | "
                     f"{r['E'] / 10.0 - 1:+.3%} | {r['nu'] / 0.3 - 1:+.3%} | {r['run_s']:.1f} |")
    return "\n".join(lines)


def record(text: str, command: str) -> None:
    """Replace (or append) this benchmark's section of RESULTS.md."""
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load = " / ".join(f"{x:.2f}" for x in os.getloadavg())
    section = (f"{BEGIN}\n## Gmsh tetrahedra against split-hex tetrahedra (issue #21)\n\n"
               f"Command: `{command}` ({stamp}; load average before the run {load} on 2 cores: "
               f"times are noisy, DOFs, qualities and errors are deterministic).\n\n{text}\n{END}")
    old = RESULTS.read_text(encoding="utf-8")
    pattern = re.compile(re.escape(BEGIN) + ".*?" + re.escape(END), re.S)
    new = pattern.sub(lambda _: section, old) if pattern.search(old) else old.rstrip() + "\n\n" + section + "\n"
    RESULTS.write_text(new, encoding="utf-8")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--record", action="store_true", help="write the tables into benchmarks/RESULTS.md")
    parser.add_argument("--coarse", action="store_true",
                        help="only the linear pair at mesh.size 8, order 1; the last line is JSON (the test)")
    args = parser.parse_args(argv)
    if args.coarse:
        rows = linear_rows(orders=(1,), levels=1, size=8.0 / 1.414)
        print(linear_table(rows))
        print(json.dumps(rows))
        return
    start = time.perf_counter()
    base = scene({"mesh.size": 4.0})
    options, points = mesh_points(base)
    cost = cost_table(base, run_points(points), options)
    linear = linear_table(linear_rows())
    text = (f"Cost study (Neo-Hookean, stretch 1.5; errors against the study's Richardson reference):\n\n{cost}\n\n"
            f"Linear model, stretch 1.01 (errors against the input E = 10 MPa, ν = 0.3):\n\n{linear}\n\n"
            f"Benchmark wall time {time.perf_counter() - start:.0f} s.")
    print(text)
    if args.record:
        record(text, "python benchmarks/gmsh_tets.py --record")


if __name__ == "__main__":
    main()
