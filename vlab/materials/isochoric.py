"""The common frame of the rubber models: ψ(F) = ψ_iso(C̄) + U(J), C̄ = J^(−2/3) C.

A model here (Mooney–Rivlin, Yeoh, Gent, Arruda–Boyce: vlab.materials.invariant; Ogden:
vlab.materials.ogden) supplies only its isochoric part (``isochoric_energy``,
``isochoric_stress``, ``isochoric_tangent``) and its initial shear modulus ``mu0``; this class
adds the volumetric part U(J) of vlab.materials.volumetric with bulk modulus ``K`` (MPa):

    ψ = ψ_iso + U(J),    P = P_iso + U'(J) J F⁻ᵀ,
    A = A_iso + U''(J) (J F⁻ᵀ) ⊗ (J F⁻ᵀ) + U'(J) J (F⁻ᵀ ⊗ F⁻ᵀ − F⁻ᵀ_iL F⁻ᵀ_kJ).

So every such model is at once a one-field Material (displacement formulation, plane stress,
homogeneous oracles, effects) and a split law of the mixed formulation (vlab.fe.mixed reads
``volume``, ``volume_gradient``, ``volume_hessian``, ``U``, ``dU``, ``d2U``, ``theta_min`` and
the isochoric methods), with no second class.

Small strain: ψ_iso ≈ μ0 |dev ε|² and U ≈ K/2 (tr ε)², so λ = K − 2μ0/3, μ = μ0,
E = 9Kμ0/(3K + μ0), ν = (3K − 2μ0)/(2(3K + μ0)) (``lmbda``, ``mu``, ``youngs_modulus``,
``poisson_ratio``: the same names as vlab.materials.base.Material, which the solver's force
floor, the locking warning and the reports read).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from vlab.materials.capabilities import LawCapabilities
from vlab.materials.split import OneFieldSplit, SplitNeoHookean
from vlab.materials.volumetric import VOLUMETRIC

__all__ = ["IsochoricVolumetric", "NonPositiveShear"]

_VOLUME = SplitNeoHookean(lmbda=1.0, mu=1.0)  # v(F) = J − 1 without cancellation, ∂J/∂F, ∂²J/∂F∂F


class NonPositiveShear(ValueError):
    """A card whose initial shear modulus μ0 is not positive (``mu0`` holds it)."""

    def __init__(self, message: str, mu0: float):
        super().__init__(message)
        self.mu0 = mu0


@dataclass(frozen=True, kw_only=True)
class IsochoricVolumetric(OneFieldSplit, LawCapabilities):
    """ψ_iso(C̄) (the subclass) + U(J) with bulk modulus K (MPa) and ``volumetric`` form."""

    K: float
    volumetric: str = "quadratic"

    name: ClassVar[str] = "abstract-split"
    is_linear: ClassVar[bool] = False
    theta_min: ClassVar[float] = 0.0  # ψ_iso = +inf at J <= 0 for every U

    def __post_init__(self) -> None:
        if not (np.isfinite(self.K) and self.K > 0.0):
            raise ValueError(f"{self.name}: bulk modulus K must be > 0 MPa, got {self.K}")
        if self.volumetric not in VOLUMETRIC:
            raise ValueError(f"{self.name}: volumetric must be one of {', '.join(VOLUMETRIC)}, "
                             f"got {self.volumetric!r}")
        if not self.mu0 > 0.0:
            raise NonPositiveShear(f"{self.name}: initial shear modulus mu0 must be > 0, got {self.mu0:g}",
                                   self.mu0)

    # --- small-strain constants ----------------------------------------------------------
    @property
    def mu0(self) -> float:  # pragma: no cover - abstract
        """Initial shear modulus μ0 = ∂²ψ_iso at C̄ = I (MPa)."""
        raise NotImplementedError

    mu = property(lambda self: self.mu0)
    kappa = property(lambda self: float(self.K))
    bulk_modulus = kappa
    lmbda = property(lambda self: self.K - 2.0 * self.mu0 / 3.0)
    youngs_modulus = property(lambda self: 9.0 * self.K * self.mu0 / (3.0 * self.K + self.mu0))
    poisson_ratio = property(lambda self: (3.0 * self.K - 2.0 * self.mu0) / (2.0 * (3.0 * self.K + self.mu0)))

    # --- volumetric part ------------------------------------------------------------------
    def volume(self, F) -> np.ndarray:
        """v(F) = J − 1 (no cancellation), shape (*batch)."""
        return _VOLUME.volume(F)

    def volume_gradient(self, F) -> np.ndarray:
        """∂J/∂F = J F⁻ᵀ, shape (3,3,*batch)."""
        return _VOLUME.volume_gradient(F)

    def volume_hessian(self, F) -> np.ndarray:
        """∂²J/∂F∂F = J (F⁻ᵀ ⊗ F⁻ᵀ − F⁻ᵀ_iL F⁻ᵀ_kJ), shape (3,3,3,3,*batch)."""
        return _VOLUME.volume_hessian(F)

    def U(self, x) -> np.ndarray:
        """U(J) at J = 1 + x, MPa (+inf where inadmissible)."""
        return self.K * VOLUMETRIC[self.volumetric].U(x)

    def dU(self, x) -> np.ndarray:
        """U'(J) at J = 1 + x, MPa (the pressure conjugate to J)."""
        return self.K * VOLUMETRIC[self.volumetric].dU(x)

    def d2U(self, x) -> np.ndarray:
        """U''(J) at J = 1 + x, MPa."""
        return self.K * VOLUMETRIC[self.volumetric].d2U(x)

    # --- the one-field law (θ = J pointwise): OneFieldSplit (vlab.materials.split) ----------
    _tangent_errstate: ClassVar[dict] = {"all": "ignore"}  # inf/nan past J <= 0 or locking: ψ = +inf there

    def describe(self) -> dict:
        """μ0, K and the small-strain E, ν this card implies (results.json → input.small_strain)."""
        return {"mu0": self.mu0, "K": self.K, "E": self.youngs_modulus, "nu": self.poisson_ratio,
                "volumetric": self.volumetric}
