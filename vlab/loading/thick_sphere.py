"""The closed form of the inflation test (vlab.loading.kinds.inflation): the incompressible
thick-walled sphere of any isotropic hyperelastic material (Green & Zerna; Ogden, Non-linear
Elastic Deformations, 1984, §5.3).

With the inner hoop stretch λ_a, the outer λ_b from incompressibility, λ_b³ = 1 + (λ_a³ − 1)(A/B)³
(A, B the reference inner and outer radii), and Ŵ(λ) = ψ(diag(λ, λ, λ⁻²)) the equibiaxial energy,
the cavity pressure is p = ∫_{λ_b}^{λ_a} Ŵ'(λ) / (λ³ − 1) dλ (MPa for ψ in MPa).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import quad

__all__ = ["thick_sphere_pressure", "outer_stretch", "equibiaxial_stress"]


def _w_prime(material, lam: float) -> float:
    """Ŵ'(λ) = 2 (P₁₁ − λ⁻³ P₃₃) at F = diag(λ, λ, λ⁻²)."""
    P = np.asarray(material.stress(np.diag([lam, lam, lam**-2])), dtype=float)
    return 2.0 * (P[0, 0] - lam**-3 * P[2, 2])


def equibiaxial_stress(material, lam: float) -> float:
    """σ_eq(λ) = λ Ŵ'(λ) / 2 (MPa): the Cauchy membrane stress σ₁ = σ₂ of an incompressible sheet in
    equibiaxial stretch λ with σ₃ = 0 (a bulge test's pole; Neo-Hookean: μ (λ² − λ⁻⁴))."""
    return 0.5 * lam * _w_prime(material, lam)


def outer_stretch(stretch, wall_ratio):
    """λ_b = (1 + (λ_a³ − 1)(A/B)³)^(1/3), the outer hoop stretch of an incompressible sphere whose
    inner hoop stretch is λ_a (``wall_ratio`` = (A/B)³); numpy arrays pass element-wise."""
    return (1.0 + (stretch**3 - 1.0) * wall_ratio) ** (1.0 / 3.0)


def thick_sphere_pressure(material, stretch: float, wall_ratio: float | None) -> float:
    """p(λ_a) of the incompressible thick sphere, ∫_{λ_b}^{λ_a} Ŵ'(λ)/(λ³ − 1) dλ with
    λ_b³ = 1 + (λ_a³ − 1)(A/B)³ (``wall_ratio`` = (A/B)³); NaN without the ratio."""
    if wall_ratio is None:
        return float("nan")
    lam_b = outer_stretch(stretch, wall_ratio)
    if stretch == 1.0:
        return 0.0

    def integrand(lam: float) -> float:
        if abs(lam - 1.0) < 1e-7:  # Ŵ'(λ)/(λ³ − 1) → Ŵ''(1)/3 at λ = 1 (Ŵ'(1) = 0)
            h = 1e-5
            return (_w_prime(material, 1.0 + h) - _w_prime(material, 1.0 - h)) / (2 * h) / 3.0
        return _w_prime(material, lam) / (lam**3 - 1.0)

    value, _ = quad(integrand, lam_b, stretch, epsabs=0.0, epsrel=1e-12, limit=200)
    return float(value)
