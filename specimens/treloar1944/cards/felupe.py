# vlab material card: ogden-3 card, volumetric quadratic -> felupe ogden (fem.ogden, eps = 1e-13)
# convention: FElupe's functions of C with vlab's constants (C10, C01, Ci0, μi, αi, C1 = μ, limit = λm); + U(J) with bulk = K
# follows: FElupe documentation, hyperelastic material models (fem.Hyperelastic, fem.Volumetric)
# units: N, mm, MPa, s, t/mm³ (vlab's units)
# bulk: K = 338.076 is an incompressible fit's stand-in (K = 999.997 μ0): the fit determines only the isochoric energy; written with U(J) = K/2 (J − 1)² (use a hybrid / mixed formulation)
# source: fit 'treloar-all' (fit.json); vlab 0.1.0, 2026-12-04
#   data uniaxial (uniaxial, fit): stretch 1 … 7.68377
#   data equibiaxial (equibiaxial, fit): stretch 1 … 4.63214
#   data pure_shear (planar, fit): stretch 1 … 5.03531
# Drucker-stable stretch range of the fitted card (vlab.identify.drucker, scanned 0.1 … 10):
#   uniaxial: tension stable up to λ = 10; compression stable down to λ = 0.1
#   equibiaxial: tension stable up to λ = 10; compression stable down to λ = 0.1
#   planar: tension stable up to λ = 10; compression stable down to λ = 0.1
import felupe as fem
from tensortrax.math import log, trace
from tensortrax.math import sum as tsum
from tensortrax.math.linalg import det, eigvalsh


def ogden(C, mu, alpha):
    """fem.ogden with eigvalsh(C, eps=1e-13): Σ 2μ/α² (λ̄1^α + λ̄2^α + λ̄3^α − 3)."""
    wC = det(C) ** (-1 / 3) * eigvalsh(C, eps=1e-13)
    return tsum([2 * m / a**2 * (tsum(wC ** (a / 2)) - 3) for m, a in zip(mu, alpha)])


umat = fem.Hyperelastic(ogden, mu=[3.8306199999999999e-02, 2.9948900000000001e-01, 2.8167300000000003e-04], alpha=[-1.3998299999999999e+00, 1.8075200000000000e+00, 6.1925800000000004e+00]) & fem.Volumetric(bulk=3.3807600000000002e+02)
