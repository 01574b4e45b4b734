"""Time the virtual camera (vlab.dic.camera) on one 1024 × 1024 level of a block's top face.

    python benchmarks/dic_camera.py [--pixels 1024] [--supersample 3] [--element-size 1.0]

A 40 × 20 × 4 mm block (hexahedra of side ``--element-size``) under a homogeneous stretch
F = diag(1.01, 0.997) on its face, seen by a camera of 36 mm field of view with 4 px speckles; the
script prints the time of the locate-and-invert step, of the speckle evaluation and of the whole
render (the best of ``--repeat`` runs, after one warm-up that compiles the numba kernel), wall
and CPU time (the CPU time is the one-core cost when other processes share the machine; run with
NUMBA_NUM_THREADS=1: the kernels are serial anyway).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pixels", type=int, default=1024)
    parser.add_argument("--supersample", type=int, default=3)
    parser.add_argument("--element-size", type=float, default=1.0)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()

    from vlab.dic import camera as cam
    from vlab.dic.face import face_of
    from vlab.dic.inverse_map import reference_points
    from vlab.geometry.block import block_mesh

    mesh = block_mesh((40.0, 20.0, 4.0), args.element_size, "hex")
    face = face_of(mesh)
    p = mesh.p
    u = np.stack([0.01 * (p[0] - 20.0), -0.003 * (p[1] - 10.0), 0 * p[0]], axis=1)
    camera = cam.Camera(pixels=(args.pixels, args.pixels), field_of_view=36.0, supersample=args.supersample,
                        noise=0.005)
    pattern = cam.paint(face, camera, cam.Speckle(size=4.0, density=0.5))
    cam.render(camera, face, pattern, u)  # warm-up: numba compiles or loads its kernel
    x1, x2 = camera.axes(face)
    best = {"invert": np.inf, "render": np.inf, "render cpu": np.inf}
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        reference_points(face.X, face.X + face.in_plane(u), face.cells, x1, x2)
        t1, c1 = time.perf_counter(), time.process_time()
        cam.render(camera, face, pattern, u)
        t2, c2 = time.perf_counter(), time.process_time()
        best["invert"] = min(best["invert"], t1 - t0)
        best["render"] = min(best["render"], t2 - t1)
        best["render cpu"] = min(best["render cpu"], c2 - c1)
    n = (args.pixels * args.supersample) ** 2
    print(f"{args.pixels} x {args.pixels} px, supersample {args.supersample} ({n / 1e6:.1f} M sub-samples), "
          f"{len(face.cells)} face cells, {len(pattern.centres)} speckles")
    print(f"locate and invert: {best['invert']:.2f} s")
    print(f"render (invert + speckle + exposure): {best['render']:.2f} s wall, {best['render cpu']:.2f} s CPU "
          f"(load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")


if __name__ == "__main__":
    main()
