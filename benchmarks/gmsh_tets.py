"""Gmsh tetrahedra against vlab's split-hex tetrahedra on an ISO 527-2 1A dumb-bell: error of E and
ν against the input (linear model, so the only error is the discretisation's) against wall time.

    python benchmarks/gmsh_tets.py        # prints a Markdown table (run on a quiet machine)

vlab: `shape = "dogbone"`, standard ISO 527-2 1A, `cell = "tet"` (each structured hex split into
tetrahedra). Gmsh: `specimens/cad/dumbbell-1a.geo` (same outline but a single 24 mm fillet), Gmsh's
Delaunay tetrahedra. Same material (linear, E = 10 MPa, ν = 0.3), clamped grips, stretch 1.01, 4
steps, extensometer over the parallel section. Runs interleaved in one process (timings on a shared
machine are noisy; DOFs and errors are deterministic).
"""

from __future__ import annotations

import time
from pathlib import Path

import vlab

ROOT = Path(__file__).resolve().parents[1]
COMMON = {"material.model": "linear", "material.E": 10.0, "material.nu": 0.3, "test.stretch": 1.01, "test.steps": 4}


def cases():
    vlab_tets = vlab.Scene.from_file(ROOT / "specimens" / "dogbone-iso527-2-1a.toml")
    gmsh_tets = vlab.Scene.from_file(ROOT / "specimens" / "dogbone-cad-1a.toml")
    for order, sizes in ((1, (4.0, 2.8, 2.0)), (2, (6.0, 4.0, 2.8))):
        for size in sizes:
            yield "vlab split hex", order, size, vlab_tets.with_values(
                COMMON | {"mesh.cell": "tet", "mesh.order": order, "mesh.size": size})
            yield "Gmsh", order, size, gmsh_tets.with_values(COMMON | {"mesh.order": order, "mesh.size": size})


def main() -> None:
    print("| mesher | order | mesh.size | DOFs | mean quality | E error | ν error | wall s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for mesher, order, size, scene in cases():
        t = time.perf_counter()
        try:
            r = scene.run()
        except vlab.SceneError as exc:
            print(f"| {mesher} | {order} | {size:g} | — | — | refused: {exc} | | |")
            continue
        wall = time.perf_counter() - t
        q = r.data["mesh"]["quality"]
        print(f"| {mesher} | {order} | {size:g} | {r.data['mesh']['dofs']} | {q['mean_quality']:.2f} | "
              f"{r.E / 10.0 - 1:+.3%} | {r.nu / 0.3 - 1:+.3%} | {wall:.1f} |", flush=True)


if __name__ == "__main__":
    main()
