"""Cost of the J2 plasticity response with its consistent tangent (vlab.materials.plasticity)
against Neo-Hookean's, on a batch of plastic points; prints seconds per call (best of repeats).

    python benchmarks/plasticity_tangent.py [--points 40000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from vlab.materials.hencky import Hencky
from vlab.materials.neo_hookean import NeoHookean
from vlab.materials.plasticity import J2Plasticity


def _best(fn, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=40000)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    lmbda, mu = 577.0, 385.0  # E = 1000 MPa, nu = 0.3
    law = J2Plasticity(Hencky(lmbda, mu), yield_stress=5.0, hardening_modulus=100.0)
    F = np.eye(3)[:, :, None] + 0.05 * rng.standard_normal((3, 3, args.points))
    state = law.update(F, law.initial_state((args.points,)), 1.0)  # hardened, anisotropic C_p
    F2 = F + 0.03 * rng.standard_normal(F.shape)
    neo = NeoHookean(lmbda, mu)
    t_plastic = _best(lambda: law.respond(F2, state, 1.0, with_tangent=True), args.repeats)
    t_stress = _best(lambda: law.respond(F2, state, 1.0, with_tangent=False), args.repeats)
    t_neo = _best(lambda: (neo.stress(F2), neo.tangent(F2)), args.repeats)
    plastic = float(np.mean(law._return(F2, state).plastic))
    print(f"points {args.points} ({100 * plastic:.0f} % plastic), best of {args.repeats}, "
          f"load average {os.getloadavg()[0]:.1f}")
    print(f"J2 respond with tangent   {t_plastic:.3f} s")
    print(f"J2 respond, stress only   {t_stress:.3f} s")
    print(f"Neo-Hookean stress+tangent {t_neo:.3f} s   ratio J2/NH {t_plastic / t_neo:.1f}")


if __name__ == "__main__":
    main()
